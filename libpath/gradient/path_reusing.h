// Gradient-domain path reusing ([GDPR] Sec. 3): the image is cut into T x T tiles, each traced as a
// (T + 1) x (T + 1) tile (one more column and row, so that every forward difference of the tile's own pixels
// has both pixels inside it, Sec. 3.2). All primary rays of a tile share one sub-pixel sample, so their pixel
// filters are equal. Every pixel traces a base path; a base path that survives Russian roulette
// (probability min(1, max(q_min, luminance / delta)), Sec. 3.3) is shifted to the primary hit of every other
// pixel of the tile (gradient/shift_mapping.h, the reuse function R of Eq. 6), and each pixel's part of it
// comes from the balance heuristic over the tile's pixels. The tile's own pixels then receive their primal
// value and their forward differences (the difference of the two pixels' parts, Eq. 8); the extra column and
// row only lend their paths. The render loop moves the tile grid by a random offset every pass (tile jitter)
// and every pixel belongs to one tile per pass, which stitches the tiles' inner parts seamlessly.
//
// Departure from the paper: its weights w_k = p_k / sum_m p_m leave out the shift Jacobians; with them, as
// here, the weights are the exact balance heuristic, and a tile of two pixels is G-PT's pair (T-GR-1).
#pragma once

#include "gradient/gradient_settings.h"
#include "image/filter_density.h"
#include "sampling/estimator_kind.h"
#include "sampling/pixel_estimator.h"

namespace lt {

class Scene;

// What a set of pixels (their primary vertices, nothing where the camera ray escaped, and their base paths)
// gives each of its pixels: every base path k with survival[k] > 0 shifted to every other pixel of the set
// and shared by the balance heuristic over the set (gradient/shift_mapping.h shareOverPixels), divided by
// survival[k]. A base path whose parts are not finite is dropped and counted in `health`.
[[nodiscard]] std::vector<Spectrum> reuseBasePaths(const Scene& scene, double shiftThreshold,
                                                   const std::vector<std::optional<BaseVertex>>& primary,
                                                   const std::vector<BasePath>& bases,
                                                   const std::vector<double>& survival, ShiftStatistics* stats,
                                                   SampleHealth& health);

class PathReusing final : public PixelEstimator {
public:
    // Its row of the estimator registry (run/estimator_registry.h).
    static const EstimatorKind Kind;

    PathReusing(const Scene& scene, GradientSettings settings);
    // Not used: the loop calls estimateTile (reuseTileSize() > 0).
    [[nodiscard]] Spectrum estimate(const Vec2& raster, SampleGenerator& sampler, PixelSample& out) const override;
    [[nodiscard]] bool tracesLightPaths() const override { return false; }
    [[nodiscard]] std::vector<std::string> planes() const override { return {"dx", "dy", "direct"}; }
    [[nodiscard]] int reuseTileSize() const override { return settings_.tile; }
    void estimateTile(const TileSample& tile) const override;
    [[nodiscard]] const ShiftStatistics& shifts() const { return stats_; }
    [[nodiscard]] std::vector<file::StatTable> statistics() const override { return {stats_.table()}; }
    [[nodiscard]] std::string summary() const override { return stats_.summary(true); }

private:
    const Scene& scene_;
    GradientSettings settings_;
    PixelRect window_;
    FilterDensity filter_;
    mutable ShiftStatistics stats_;
};

} // namespace lt
