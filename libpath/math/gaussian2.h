// An anisotropic 2-D Gaussian with principal axes (axis, its perpendicular) and standard deviations
// (sigma1, sigma2): the half-vector kernel of HSLT (Kaplanyan, Hanika & Dachsbacher 2014, Sec. 6-7; the
// Gaussian form of their anisotropic lobe, see mcmc/mutations/half_vector_mutation.h).
#pragma once

#include <cmath>

#include "math/constants.h"
#include "math/rng.h"
#include "math/vec.h"

namespace lt {

struct Gaussian2 {
    Vec2 axis{1, 0}; // unit: the first principal axis
    double sigma1 = 1, sigma2 = 1;

    [[nodiscard]] Vec2 second() const { return {-axis.y, axis.x}; }
    [[nodiscard]] Vec2 sample(const Vec2& mean, Pcg32& rng) const {
        const double u = rng.nextDouble(), v = rng.nextDouble();
        const auto g = standardNormalPair(u, v);
        return mean + axis * (g[0] * sigma1) + second() * (g[1] * sigma2);
    }
    [[nodiscard]] double density(const Vec2& mean, const Vec2& x) const {
        const Vec2 d = x - mean;
        const double a = dot(d, axis) / sigma1, b = dot(d, second()) / sigma2;
        return std::exp(-0.5 * (a * a + b * b)) / (2 * Pi * sigma1 * sigma2);
    }
};

} // namespace lt
