// The contract of a pixel estimator: what the render loop (sampling/render.h) asks of BDPT, the path
// tracer, and the gradient-domain estimators after them. One camera sample through a raster position
// returns the estimate for its own pixel's primal image, and may add splats anywhere on the film and
// values for further named planes of the film (gradients, direct light, ...) at its own pixel or its
// neighbours. The loop owns the tiles, passes, random streams, merging, snapshots and the clock, so an
// estimator is only the per-sample work (as pbrt-v4's EvaluatePixelSample and Tungsten's traceSample).
#pragma once

#include <string>
#include <vector>

#include "formats/records.h"
#include "image/film.h"
#include "math/spectrum.h"
#include "math/vec.h"
#include "path/sample_health.h"
#include "path/splat.h"
#include "path/strategy_path.h"
#include "sampling/sample_generator.h"

namespace lt {

// A value for plane `plane` (an index into PixelEstimator::planes(), or PrimalPlane) of the pixel (dx, dy)
// away from the sample's own. The film averages each plane over the camera samples of the pixel it lands on.
// The gradient-domain estimators credit a neighbour's primal image with what a shifted path found there.
inline constexpr int PrimalPlane = -1;

struct PlaneValue {
    int plane = 0;
    int dx = 0, dy = 0;
    Spectrum value;
};

// One camera sample: the pixel its primal value is credited to (its raster position is drawn from the
// pixel filter around it, and may lie in a neighbour), and where it puts what it found besides that
// value.
struct PixelSample {
    int x = 0, y = 0;                         // the pixel, full-film coordinates
    std::vector<Splat>& splats;               // anywhere on the film (divided by the light paths traced)
    std::vector<PlaneValue>& planes;          // the estimator's further planes
    SampleHealth& health;                     // non-finite results, counted and dropped
    const StrategyCallback* onPath = nullptr; // sees every joined path (seed paths of the Markov chains)
};

// A tile for estimators that reuse paths across the pixels of a tile (gradient-domain path reusing): the
// loop hands over the tile's pixels and its result (sum and count laid out for `rect`, zero), and the
// estimator fills them and the further planes.
struct TileSample {
    PixelRect rect;    // the tile's pixels, inside the film window
    uint64_t seed = 0; // the run's seed
    int pass = 0;      // the sample pass: every pixel lies in exactly one tile per pass
    TileResult& result;
    SampleHealth& health;
};

class PixelEstimator {
public:
    virtual ~PixelEstimator() = default;

    // One sample through `raster` (pixels of the full film), with random numbers from `sampler`.
    [[nodiscard]] virtual Spectrum estimate(const Vec2& raster, SampleGenerator& sampler, PixelSample& out) const = 0;

    // Whether each sample traces one light subpath whose splats the film divides by the number of such
    // subpaths (light tracing in BDPT); false for estimators without splats.
    [[nodiscard]] virtual bool tracesLightPaths() const = 0;

    // The film's planes besides the primal image, by name as formats/SPEC.md spells them ("dx", "dy",
    // "direct"); none for BDPT and the path tracer.
    [[nodiscard]] virtual std::vector<std::string> planes() const { return {}; }

    // Whether a sample credits other pixels than its own with primal or plane values (G-PT's shifted
    // paths): a pixel's value for a pass is then complete only when the whole pass is, and a time limit
    // waits for the end of the pass. Otherwise a run may end after any work item.
    [[nodiscard]] virtual bool creditsNeighbours() const { return false; }

    // T > 0: the estimator works a T x T tile at a time (estimateTile instead of estimate), and the loop
    // moves the tile grid by a random offset every pass ([GDPR] Sec. 3.2, tile jitter). 0: pixel by pixel.
    [[nodiscard]] virtual int reuseTileSize() const { return 0; }
    // One sample for every pixel of the tile (only called when reuseTileSize() > 0).
    virtual void estimateTile(const TileSample& tile) const { (void)tile; }

    // What the estimator counted over a run, as files store it, and as a few words for the user (the
    // gradient-domain estimators: how their shifts ended); nothing by default.
    [[nodiscard]] virtual std::vector<file::StatTable> statistics() const { return {}; }
    [[nodiscard]] virtual std::string summary() const { return {}; }
};

} // namespace lt
