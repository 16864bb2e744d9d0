// Gradient-domain path tracing (G-PT; Kettunen et al. 2015, Sec. 5 and 6): every base path is shifted to
// its four neighbours, and each pixel pair (i, j) estimates I_i, I_j and the difference I_j - I_i with the
// symmetric balance weights over "sampled in i" and "sampled in j and shifted" ([GDPR] Eq. 5). Each pixel
// takes part in four pairs, so its primal value is the mean of its four pair estimates; a neighbour outside
// the film window is no technique, and the base path then stands alone for that pair. Writes the planes
// "dx", "dy" (forward differences, formats/SPEC.md) and "direct" (emitters seen directly, kept out of the
// primal image and the gradients and added back after the reconstruction).
#pragma once

#include "gradient/gradient_settings.h"
#include "image/film.h"
#include "sampling/estimator_kind.h"
#include "sampling/pixel_estimator.h"

namespace lt {

class Scene;

class GradientPathTracer final : public PixelEstimator {
public:
    // Its row of the estimator registry (run/estimator_registry.h).
    static const EstimatorKind Kind;

    GradientPathTracer(const Scene& scene, GradientSettings settings);
    [[nodiscard]] Spectrum estimate(const Vec2& raster, SampleGenerator& sampler, PixelSample& out) const override;
    [[nodiscard]] bool tracesLightPaths() const override { return false; }
    [[nodiscard]] std::vector<std::string> planes() const override { return {"dx", "dy", "direct"}; }
    [[nodiscard]] bool creditsNeighbours() const override { return true; }
    [[nodiscard]] const ShiftStatistics& shifts() const { return stats_; }
    [[nodiscard]] std::vector<file::StatTable> statistics() const override { return {stats_.table()}; }
    [[nodiscard]] std::string summary() const override { return stats_.summary(false); }

private:
    const Scene& scene_;
    GradientSettings settings_;
    PixelRect window_;
    mutable ShiftStatistics stats_;
};

} // namespace lt
