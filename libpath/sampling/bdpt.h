// Bidirectional path tracing (Veach thesis ch. 10; Veach and Guibas 1995): one camera subpath and one
// light subpath per sample, joined by every (s, t) strategy, light tracing (t = 1) and emitters hit by
// the camera subpath (s = 0) included, weighted by multiple importance sampling.
#pragma once

#include <functional>
#include <vector>

#include "path/vertex.h"
#include "sampling/mis.h"
#include "sampling/sample_generator.h"

namespace lt {

struct BdptSettings {
    int maxDepth = -1;          // Mitsuba's meaning: the most edges a path may have (-1: unbounded)
    int rrDepth = 5;            // from this many edges on, subpaths continue by Russian roulette
    MisHeuristic mis = MisHeuristic::Power;
    // For tests: evaluate only this one strategy, unweighted (each strategy alone is unbiased for the
    // paths it can sample). -1 = all strategies with MIS.
    int onlyS = -1, onlyT = -1;
};

// Russian roulette survival probability from the throughput relative to the path's start (Mitsuba 0.5,
// pbrt-v4): q = min(0.95, max component of beta times etaScale). etaScale, the product of eta^2 over the
// refractions so far, undoes the radiance compression of entering a denser medium, so paths inside glass
// are not killed for it.
[[nodiscard]] inline double russianRouletteSurvival(const Spectrum& relativeBeta, double etaScale) {
    const double q = relativeBeta.maxValue() * etaScale;
    return q < 0.95 ? q : 0.95;   // NaN compares false: a NaN throughput survives and is counted later
}

// A contribution that lands away from the sample's own pixel: light tracing (t = 1) connects to the
// camera at any raster position.
struct Splat {
    Vec2 raster;
    Spectrum value;
};

// One joined path as the strategy (s, t) produced it, for seed-path output and inspection.
struct StrategyPath {
    int s = 0, t = 0;
    const std::vector<PathVertex>* light = nullptr;   // light subpath, the first s vertices used
    const std::vector<PathVertex>* camera = nullptr;  // camera subpath, the first t vertices used
    const PathVertex* sampled = nullptr;              // the vertex that replaced light[0] (s = 1) or camera[0] (t = 1)
    Vec2 raster;
    Spectrum unweighted;                              // f / p of the strategy
    double misWeight = 0;
};
using StrategyCallback = std::function<void(const StrategyPath&)>;

// Counts of samples that produced NaN or Inf and were dropped (never written to an output).
struct SampleHealth {
    uint64_t nonFinite = 0;
};

class Bdpt {
public:
    // Throws lt::Error if maxDepth is 0 or below -1.
    Bdpt(const Scene& scene, BdptSettings settings);

    // One sample through raster position `raster` (pixels of the full film): returns the estimate for
    // the sample's own pixel and appends light-tracing contributions to `splats`.
    [[nodiscard]] Spectrum sample(const Vec2& raster, SampleGenerator& sampler, std::vector<Splat>& splats,
                                  SampleHealth& health, const StrategyCallback* onPath = nullptr) const;

    // The subpath generators, exposed for tests and for the Markov chains that reuse them. `maxVertices`
    // bounds the subpath below the limit maxDepth sets (0: that limit); multiplexed MLT asks for exactly
    // the s or t vertices of its technique.
    void cameraSubpath(const Vec2& raster, SampleGenerator& sampler, std::vector<PathVertex>& path,
                       size_t maxVertices = 0) const;
    void lightSubpath(SampleGenerator& sampler, std::vector<PathVertex>& path, size_t maxVertices = 0) const;

    // One strategy (s, t) on given subpaths (at least s light and t camera vertices): its MIS-weighted
    // contribution, zero when it does not connect. For t = 1 the contribution is a splat at `raster`.
    [[nodiscard]] Spectrum strategy(std::vector<PathVertex>& light, std::vector<PathVertex>& camera, int s, int t,
                                    SampleGenerator& sampler, Vec2& raster) const;

private:
    // Continue a subpath from its last vertex along `ray`, whose direction had solid-angle density pdfDir.
    void randomWalk(Ray ray, Spectrum beta, double pdfDir, SampleGenerator& sampler, Transport mode, size_t maxVertices,
                    std::vector<PathVertex>& path) const;
    // The (s, t) strategy: its unweighted contribution, with the sampled endpoint and raster position
    // when it makes one; MIS weight in `weight`.
    Spectrum connect(std::vector<PathVertex>& light, std::vector<PathVertex>& camera, int s, int t,
                     SampleGenerator& sampler, Vec2& raster, PathVertex& sampled, double& weight) const;
    double misWeight(std::vector<PathVertex>& light, std::vector<PathVertex>& camera, const PathVertex& sampled,
                     int s, int t) const;

    const Scene& scene_;
    BdptSettings settings_;
    size_t maxCameraVertices_, maxLightVertices_;
};

} // namespace lt
