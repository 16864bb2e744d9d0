// Unidirectional path tracing with next-event estimation, the two strategies (BSDF sampling hitting an
// emitter, and a direct light sample at every vertex) combined by MIS (Veach thesis 9.2). It estimates
// the same pixel measurement as Bdpt::sample (camera strategies only, no splats).
#pragma once

#include "sampling/bdpt.h"

namespace lt {

class PathTracer {
public:
    PathTracer(const Scene& scene, BdptSettings settings);
    [[nodiscard]] Spectrum sample(const Vec2& raster, SampleGenerator& sampler, SampleHealth& health) const;

private:
    const Scene& scene_;
    BdptSettings settings_;
};

} // namespace lt
