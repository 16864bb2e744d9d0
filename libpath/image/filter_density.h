// The pixel filter as a normalized density, used two ways that must agree exactly (Veach thesis 10.3.1,
// "the same measurement for every strategy"): camera samples are drawn from it around their pixel's
// center and credited to that pixel with weight 1, and light-tracing splats are spread over the pixels
// around them with its value as weight. Box and tent are exact; the truncated gaussian is tabulated
// (a piecewise-constant density that is then the filter for both uses).
#pragma once

#include <vector>

#include "math/vec.h"
#include "scene/camera.h"

namespace lt {

class FilterDensity {
public:
    explicit FilterDensity(const PixelFilter& filter);

    [[nodiscard]] double radius() const { return radius_; }
    // Offset from the pixel center, distributed with the normalized filter.
    [[nodiscard]] Vec2 sample(const Vec2& u) const { return {sample1D(u.x), sample1D(u.y)}; }
    // The normalized filter value at an offset (integrates to 1 over the plane, in pixel units).
    [[nodiscard]] double eval(const Vec2& d) const { return eval1D(d.x) * eval1D(d.y); }

private:
    [[nodiscard]] double sample1D(double u) const;
    [[nodiscard]] double eval1D(double x) const;

    PixelFilter::Type type_;
    double radius_;
    std::vector<double> cdf_, pdf_;   // gaussian: tabulated over [-radius, radius]
};

} // namespace lt
