#include "mcmc/mutation_registry.h"

#include "mcmc/mutations/bidirectional_mutation.h"
#include "mcmc/mutations/caustic_perturbation.h"
#include "mcmc/mutations/half_vector_mutation.h"
#include "mcmc/mutations/lens_perturbation.h"
#include "mcmc/mutations/lens_subpath_mutation.h"
#include "mcmc/mutations/manifold_perturbation.h"
#include "mcmc/mutations/multi_chain_perturbation.h"
#include "mcmc/mutations/portal_perturbation.h"

namespace lt {

namespace {

const MutationKind* const Kinds[] = {
    &BidirectionalMutation::Kind,  //
    &LensPerturbation::Kind,       //
    &CausticPerturbation::Kind,    //
    &MultiChainPerturbation::Kind, //
    &LensSubpathMutation::Kind,    //
    &ManifoldPerturbation::Kind,   //
    &HalfVectorMutation::Kind,     //
    &PortalPerturbation::Kind,     //
};

} // namespace

MutationKinds mutationKinds() { return Kinds; }

const MutationKind* findMutationKind(const std::string& name, MutationKinds kinds) {
    for (const MutationKind* k : kinds)
        if (name == k->name) return k;
    return nullptr;
}

} // namespace lt
