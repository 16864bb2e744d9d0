// Unidirectional path tracing with next-event estimation, the two strategies (BSDF sampling hitting an
// emitter, and a direct light sample at every vertex) combined by MIS (Veach thesis 9.2). It estimates
// the same pixel measurement as Bdpt::sample (camera strategies only, no splats).
#pragma once

#include "sampling/estimator_kind.h"
#include "sampling/path_settings.h"
#include "sampling/pixel_estimator.h"

namespace lt {

class PathTracer final : public PixelEstimator {
public:
    // Its row of the estimator registry (run/estimator_registry.h).
    static const EstimatorKind Kind;

    PathTracer(const Scene& scene, PathSettings settings);
    [[nodiscard]] Spectrum sample(const Vec2& raster, SampleGenerator& sampler, SampleHealth& health) const;
    // As a pixel estimator: sample(); no splats, no further planes, no joined paths.
    [[nodiscard]] Spectrum estimate(const Vec2& raster, SampleGenerator& sampler, PixelSample& out) const override {
        return sample(raster, sampler, out.health);
    }
    [[nodiscard]] bool tracesLightPaths() const override { return false; }

private:
    const Scene& scene_;
    PathSettings settings_;
};

} // namespace lt
