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

std::string always(const SceneFeatures&) { return {}; }

// The caustic and multi-chain perturbations move only paths through specular chains (Veach and Guibas
// 1997): without one in the scene they could never propose anything. The manifold perturbation would
// move other paths too, but only as a lens perturbation with quarter-pixel steps; on scenes with
// specular chains auto adds it to Veach's perturbations rather than replacing them (Jakob and Marschner's
// MEMLT is bidirectional + manifold alone): at equal time that mix measured best on veach-bidir's egg
// and matched MEMLT on caustic-mirror (pipelines/results/memlt/README.md).
std::string needsSpecularChains(const SceneFeatures& features) {
    return features.specularChains ? std::string() : features.specularReason;
}

// The manifold perturbation also walks glossy chains (their vertices held on offset manifolds, ME Sec.
// 5.2): on glossy-caustic, auto's bidirectional + lens measured relMSE 0.029 at 60 s and with the
// manifold perturbation added 0.017 (pipelines/results/memlt/README.md).
std::string needsSpecularOrGlossyChains(const SceneFeatures& features) {
    if (features.specularChains || features.glossySurfaces) return {};
    return "no delta or glossy BSDF: no specular or glossy chain to walk";
}

std::string optional(const SceneFeatures&) {
    return "optional (Veach 1997; Mitsuba dropped it for want of a gain); ask for it with --strategies";
}

// The portal perturbation moves only edges that cross a portal (Otsu et al. Sec. 4.5: suitability 0
// elsewhere). The paper mixes bidirectional : (lens : portal = 1 : 1) = 1 : 1; auto gives every chosen
// strategy weight 1.
std::string needsPortals(const SceneFeatures& features) {
    return features.hasPortals ? std::string() : features.portalReason;
}

// HSLT mutates every half vector of a path at once (the paper pairs it with the bidirectional mutation
// alone). Added to auto's own mix it did not help at equal time (120 s, 2 cores, relMSE auto against auto
// + hslt: glossy-rings 0.300 / 0.308, veach-mis 0.330 / 0.373, veach-bidir 0.254 / 0.709;
// pipelines/results/hslt/README.md).
std::string askForHslt(const SceneFeatures&) {
    return "measured no better added to auto's mix on glossy, mixed and caustic scenes (pipelines/results/hslt); "
           "ask for it with --strategies";
}

const MutationKind Kinds[] = {
    {"bidirectional", "mutation", "replaces any part of a path; required: the others alone are not ergodic",
     [](const Scene& s, const MutationSettings& m) -> std::unique_ptr<Mutation> {
         return std::make_unique<BidirectionalMutation>(s, m.maxEdges);
     },
     always},
    {"lens", "perturbation", "moves the eye end of (L|D) D S* E paths to a nearby raster position",
     [](const Scene& s, const MutationSettings&) -> std::unique_ptr<Mutation> {
         return std::make_unique<LensPerturbation>(s);
     },
     always},
    {"caustic", "perturbation",
     "turns the light end of (L|D) S+ D E paths (moves a sky's or sun's ray sideways): caustics on a diffuse "
     "surface seen directly",
     [](const Scene& s, const MutationSettings&) -> std::unique_ptr<Mutation> {
         return std::make_unique<CausticPerturbation>(s);
     },
     needsSpecularChains},
    {"multi-chain", "perturbation", "the lens perturbation carried through D S+ D S* E paths, chain after chain",
     [](const Scene& s, const MutationSettings&) -> std::unique_ptr<Mutation> {
         return std::make_unique<MultiChainPerturbation>(s);
     },
     needsSpecularChains},
    {"lens-subpath", "mutation", "a fresh eye end of (L|D) D S* E paths through a random raster position",
     [](const Scene& s, const MutationSettings& m) -> std::unique_ptr<Mutation> {
         return std::make_unique<LensSubpathMutation>(s, m.maxEdges);
     },
     optional},
    {"manifold", "perturbation",
     "manifold exploration: turns a direction and walks the specular or glossy chain after it (caustics seen "
     "through glass and mirrors)",
     [](const Scene& s, const MutationSettings& m) -> std::unique_ptr<Mutation> {
         return std::make_unique<ManifoldPerturbation>(s, m.lambda, m.normalChange);
     },
     needsSpecularOrGlossyChains},
    {"hslt", "mutation",
     "half-vector space light transport: new half vectors at every non-specular vertex at once, the light point "
     "or direction and the camera kept (glossy interreflections)",
     [](const Scene& s, const MutationSettings& m) -> std::unique_ptr<Mutation> {
         return std::make_unique<HalfVectorMutation>(s, m.hsltGamma, m.hsltStratify, m.hsltJumps);
     },
     askForHslt},
    {"portal", "perturbation",
     "turns the edge crossing a portal (a window, a door ajar) about its crossing point: light entering a room "
     "through a small opening",
     [](const Scene& s, const MutationSettings& m) -> std::unique_ptr<Mutation> {
         return std::make_unique<PortalPerturbation>(s, ReciprocalKernel{m.portalMin, m.portalMax});
     },
     needsPortals},
};

} // namespace

std::span<const MutationKind> mutationKinds() { return Kinds; }

const MutationKind* findMutationKind(const std::string& name) {
    for (const auto& k : Kinds)
        if (name == k.name) return &k;
    return nullptr;
}

} // namespace lt
