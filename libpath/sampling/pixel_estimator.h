// The contract of a pixel estimator: what the render loop (sampling/render.h) asks of BDPT, the path
// tracer, and any estimator after them. One camera sample through a raster position returns the estimate
// for the sample's own pixel and may add contributions elsewhere on the film (splats); the loop owns
// the tiles, passes, random streams, merging, snapshots and the clock, so an estimator is only the
// per-sample work (as pbrt-v4's EvaluatePixelSample and Tungsten's traceSample).
#pragma once

#include <vector>

#include "math/spectrum.h"
#include "math/vec.h"
#include "path/sample_health.h"
#include "path/splat.h"
#include "path/strategy_path.h"
#include "sampling/sample_generator.h"

namespace lt {

class PixelEstimator {
public:
    virtual ~PixelEstimator() = default;

    // One sample through `raster` (pixels of the full film), with random numbers from `sampler`: the
    // estimate for the sample's pixel; splats appended to `splats`; non-finite results counted in
    // `health` and dropped. `onPath`, when given, sees every joined path the estimator forms (the seed
    // paths of the Markov chains); estimators that form none ignore it.
    [[nodiscard]] virtual Spectrum sample(const Vec2& raster, SampleGenerator& sampler, std::vector<Splat>& splats,
                                          SampleHealth& health, const StrategyCallback* onPath) const = 0;

    // Whether each sample traces one light subpath whose splats the film divides by the number of such
    // subpaths (light tracing in BDPT); false for estimators without splats.
    [[nodiscard]] virtual bool tracesLightPaths() const = 0;
};

} // namespace lt
