// Bidirectional path tracing (Veach thesis ch. 10; Veach and Guibas 1995): one camera subpath and one
// light subpath per sample, joined by every (s, t) strategy, light tracing (t = 1) and emitters hit by
// the camera subpath (s = 0) included, weighted by multiple importance sampling.
#pragma once

#include <vector>

#include "path/sample_health.h"
#include "path/splat.h"
#include "path/strategy_path.h"
#include "path/vertex.h"
#include "sampling/estimator_kind.h"
#include "sampling/mis.h"
#include "sampling/path_settings.h"
#include "sampling/pixel_estimator.h"
#include "sampling/sample_generator.h"

namespace lt {

class Bdpt final : public PixelEstimator {
public:
    // Its row of the estimator registry (run/estimator_registry.h).
    static const EstimatorKind Kind;

    // Throws lt::Error if maxDepth is 0 or below -1.
    Bdpt(const Scene& scene, PathSettings settings);

    // One sample through raster position `raster` (pixels of the full film): returns the estimate for
    // the sample's own pixel and appends light-tracing contributions to `splats`.
    [[nodiscard]] Spectrum sample(const Vec2& raster, SampleGenerator& sampler, std::vector<Splat>& splats,
                                  SampleHealth& health, const StrategyCallback* onPath) const;
    // As a pixel estimator: sample().
    [[nodiscard]] Spectrum estimate(const Vec2& raster, SampleGenerator& sampler, PixelSample& out) const override {
        return sample(raster, sampler, out.splats, out.health, out.onPath);
    }
    [[nodiscard]] bool tracesLightPaths() const override { return true; }

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
    PathSettings settings_;
    size_t maxCameraVertices_, maxLightVertices_;
};

} // namespace lt
