// The integrands of the primary-sample-space chains (MCMC survey, Sec. 4.1-4.2): BDPT driven by a vector of
// numbers u in [0, 1)^d instead of independent ones.
// * Kelemen PSSMLT: the whole BDPT sample (every (s, t) strategy, MIS-weighted) is one state; its target
//   is the luminance of everything it contributes (SURVEY Eq. 19).
// * Multiplexed MLT (Hachisuka et al. 2014): for paths of a given number of edges, the first number
//   picks ONE strategy (s, t) uniformly; the target is (number of strategies) x w_st f / p_st (SURVEY
//   Eq. 20), so the MIS weight inside the target steers the chain to the strategy that suits the path.
//   Chains are grouped by path length as in pbrt-v3.
//
// The raster position comes from u uniformly over the sensor window (the crop window grown by the pixel
// filter's radius), so the image integral I_j = integral of h_j(r) L(r) dr gets the estimate
// A_sensor L(r) h_j(r); a light-tracing strategy's value is per light path, like in the film, and gets
// the factor (crop pixels). The integral of the target over u is then the normalization b of the chain.
#pragma once

#include <vector>

#include "image/film.h"
#include "mcmc/image_contribution.h"
#include "mcmc/sensor_window.h"
#include "sampling/bdpt.h"

namespace lt {

class PrimarySpaceTarget {
public:
    // The path length of multiplexed chains is bounded: with maxDepth -1 (unbounded) the bound is
    // `unboundedEdges`, and tools say so.
    PrimarySpaceTarget(const Scene& scene, const PathSettings& settings, int unboundedEdges = 12);

    // Kelemen PSSMLT: the contributions of the full BDPT sample u; returns their target value.
    double evaluateAll(SampleGenerator& u, std::vector<ImageContribution>& out, SampleHealth& health) const;
    // Multiplexed MLT for paths of `edges` edges (minEdges() .. maxEdges(); 0 for other lengths).
    double evaluateMultiplexed(int edges, SampleGenerator& u, std::vector<ImageContribution>& out,
                               SampleHealth& health) const;

    [[nodiscard]] int minEdges() const { return minEdges_; }
    [[nodiscard]] int maxEdges() const { return maxEdges_; }

private:
    Bdpt bdpt_;
    Bdpt fixedLength_; // multiplexed: no Russian roulette, subpaths have exactly s and t vertices
    int minEdges_, maxEdges_;
    SensorWindow sensor_;
    double cropPixels_;
};

} // namespace lt
