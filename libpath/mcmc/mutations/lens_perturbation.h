// Veach and Guibas' lens perturbation (Veach thesis 11.4.3) for paths whose eye end is
// (L|D) D S* E: move the raster position by an offset of length r in [r1, r2] (density 1 / (r ln(r2 /
// r1)), uniform angle), trace the new camera ray through the specular chain keeping each vertex's lobe
// kind to the first non-specular vertex x_j', and connect it to the unchanged x_{j-1}.
//
// T in the measure of f: the state's changed vertices x_j' .. x_{k-1}' are a function of the raster
// position, so T(x -> y) = p_offset(r) |d raster / d x_{k-1}'| x (the stripped densities of the chain's
// vertices with the lobes fixed): p_offset(r) eyeChainDensity(y) (specular_chain.h).
// p_offset is symmetric and cancels in the ratio, the Jacobians do not. Through a thin lens the lens point
// moves too, by a symmetric kernel (specular_chain.h perturbCamera) that cancels as p_offset does; the
// Jacobians are then those of the new lens point's chain.
#pragma once

#include "mcmc/mutation.h"
#include "mcmc/mutation_registry.h"
#include "mcmc/mutations/specular_chain.h"

namespace lt {

class LensPerturbation final : public Mutation {
public:
    // Its row of the registry (mcmc/mutation_registry.h).
    static const MutationKind Kind;

    explicit LensPerturbation(const Scene& scene);

    [[nodiscard]] std::string name() const override { return Kind.name; }
    [[nodiscard]] bool suitable(const MarkovPath& x) const override;
    void propose(const MarkovPath& x, Pcg32& rng, Proposal& out) const override;

private:
    const Scene& scene_;
    SensorWindow sensor_;
    ReciprocalKernel radius_;
};

} // namespace lt
