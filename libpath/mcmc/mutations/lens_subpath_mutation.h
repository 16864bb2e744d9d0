// Veach's lens subpath mutation (Veach thesis ch. 11) for paths whose eye end is
// (L|D) D S* E: delete the lens subpath x_j .. x_{k-1} (the first non-specular vertex seen from the camera
// and the specular chain in front of it) and trace a fresh one through a raster position uniform over the
// sensor window: at each hit choose a delta lobe with its own probability and go on, or stop there with
// the remaining probability (the new x_j', a vertex scattering through its non-delta lobes), then connect
// x_j' to the unchanged x_{j-1}. Veach chose the pixels of successive lens-subpath mutations in a
// stratified order, to cover the image evenly; lt draws each one uniformly, which keeps the mutation a
// plain Metropolis-Hastings kernel with the density below.
//
// T in the measure of f: the new subpath is an eye random walk that stops by its own coin, so
// T(x -> y) = (stripped eye densities of x_j' .. x_{k-1}', markov_path.h's densityFromEye) x P_stop(x_j'),
// with P_stop = 1 - (probability of the delta lobes at x_j' given the direction to the eye). It does not
// depend on x, so the ratio T(y -> x) / T(x -> y) compares the two lens subpaths alone.
#pragma once

#include "mcmc/mutation.h"
#include "mcmc/mutation_registry.h"
#include "mcmc/sensor_window.h"

namespace lt {

class LensSubpathMutation final : public Mutation {
public:
    // Its row of the registry (mcmc/mutation_registry.h).
    static const MutationKind Kind;

    // maxEdges: the longest path the chain may reach (as for the bidirectional mutation).
    LensSubpathMutation(const Scene& scene, int maxEdges);

    [[nodiscard]] std::string name() const override { return Kind.name; }
    [[nodiscard]] bool suitable(const MarkovPath& x) const override;
    void propose(const MarkovPath& x, Pcg32& rng, Proposal& out) const override;

    // The density of generating the lens subpath x_j .. x_{k-1} of `v` (j its first non-specular vertex
    // from the eye), including the probability of stopping at x_j.
    [[nodiscard]] double subpathDensity(const std::vector<PathVertex>& v, int j) const;

private:
    const Scene& scene_;
    int maxEdges_;
    SensorWindow sensor_;
};

} // namespace lt
