// Veach and Guibas' multi-chain perturbation (Veach thesis 11.4.4) for paths whose eye
// end is D S+ D S* E, possibly with more specular chains behind, ending at the first pair of adjacent
// non-specular vertices (the light counts as one): a lens perturbation through the first chain to x_j';
// then at each further non-specular vertex x_d' the OLD direction x_d -> x_{d-1} is turned by an angle
// with density proportional to 1 / theta on [1e-4, 0.1] degrees (Mitsuba's values) and followed through
// the next chain, lobe kinds kept; the last such vertex x_c' is connected to the unchanged x_{c-1}.
//
// T in the measure of f: the lens perturbation's eyeChainDensity for the first chain, then for each
// turned direction its solid-angle density converted to the area of the next vertex, times the fixed-lobe
// densities from the eye through the chain. The raster and angle kernels depend only on the offset
// (the same range at every state), so they are symmetric; the Jacobians are not and stay in T.
#pragma once

#include "mcmc/mutation.h"
#include "mcmc/mutation_registry.h"
#include "mcmc/mutations/specular_chain.h"

namespace lt {

class MultiChainPerturbation final : public Mutation {
public:
    // Its row of the registry (mcmc/mutation_registry.h).
    static const MutationKind Kind;

    explicit MultiChainPerturbation(const Scene& scene);

    [[nodiscard]] std::string name() const override { return Kind.name; }
    [[nodiscard]] bool suitable(const MarkovPath& x) const override;
    void propose(const MarkovPath& x, Pcg32& rng, Proposal& out) const override;

    // The non-specular vertices the perturbation moves, eye to light: x_j, the ones ending the further
    // chains, and last x_c (x_{c-1} non-specular); empty when the path is not of the form.
    [[nodiscard]] static std::vector<int> stops(const MarkovPath& path);
    // T(x -> y) for the path `path` reached by the raster offset density pOffset and the turns `thetas`
    // (one per stop but the last).
    [[nodiscard]] double density(const MarkovPath& path, double pOffset, const std::vector<double>& thetas) const;

private:
    const Scene& scene_;
    SensorWindow sensor_;
    ReciprocalKernel radius_, angle_;
};

} // namespace lt
