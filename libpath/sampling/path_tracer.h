// Unidirectional path tracing with next-event estimation, the two strategies (BSDF sampling hitting an
// emitter, and a direct light sample at every vertex) combined by MIS (Veach thesis 9.2). It estimates
// the same pixel measurement as Bdpt::sample (camera strategies only, no splats).
#pragma once

#include "sampling/path_settings.h"
#include "sampling/pixel_estimator.h"

namespace lt {

class PathTracer final : public PixelEstimator {
public:
    PathTracer(const Scene& scene, PathSettings settings);
    // No splats and no joined paths: `splats` and `onPath` are left alone.
    [[nodiscard]] Spectrum sample(const Vec2& raster, SampleGenerator& sampler, std::vector<Splat>& splats,
                                  SampleHealth& health, const StrategyCallback* onPath) const override;
    [[nodiscard]] bool tracesLightPaths() const override { return false; }

private:
    const Scene& scene_;
    PathSettings settings_;
};

} // namespace lt
