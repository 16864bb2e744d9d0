// The von Mises-Fisher distribution on the unit sphere, the direction kernel of the manifold perturbation
// (Jakob & Marschner 2012, Sec. 5.1): density D(w) = kappa e^{kappa (mu.w - 1)} / (2 pi (1 - e^{-2 kappa}))
// in solid angle around the mean direction mu. Written so that no step overflows or cancels at the huge
// concentrations near-specular BSDFs ask for (kappa 1e6 and beyond): mu.w - 1 as -|mu - w|^2 / 2, the
// normalization with expm1, the inverse CDF in log form and the polar angle from 1 - cos theta.
#pragma once

#include <cmath>

#include "math/constants.h"
#include "math/frame.h"

namespace lt {

struct VonMisesFisher {
    double kappa = 0; // concentration; 0 is the uniform sphere

    // The concentration whose density at the mean direction is `peak` (per steradian): kappa solves
    // kappa / (2 pi (1 - e^{-2 kappa})) = peak. At most 1 / (4 pi), the uniform density, gives kappa 0.
    [[nodiscard]] static VonMisesFisher withPeak(double peak) {
        const double P = 2 * Pi * peak; // kappa / (1 - e^{-2 kappa}) = P, an increasing function from 1/2
        if (!(P > 0.5)) return {0};
        if (!std::isfinite(P)) return {P};
        double kappa = P; // exact once e^{-2 kappa} is negligible; Newton from above otherwise (g is convex)
        for (int i = 0; i < 100; ++i) {
            const double e = std::exp(-2 * kappa), g = kappa + P * std::expm1(-2 * kappa), dg = 1 - 2 * P * e;
            const double next = kappa - g / dg;
            if (!(next > 0) || std::abs(next - kappa) <= 1e-14 * kappa) break;
            kappa = next;
        }
        return {kappa};
    }

    // Solid-angle density of unit direction w around unit mean mu.
    [[nodiscard]] double density(const Vec3& mu, const Vec3& w) const {
        if (!(kappa > 0)) return 1 / (4 * Pi);
        const Vec3 d = mu - w;
        return kappa * std::exp(-kappa * 0.5 * dot(d, d)) / (2 * Pi * -std::expm1(-2 * kappa));
    }

    // A direction around unit mean mu from two uniform numbers.
    [[nodiscard]] Vec3 sample(const Vec3& mu, double u1, double u2) const {
        // 1 - cos theta = -log(u1 + (1 - u1) e^{-2 kappa}) / kappa, in [0, 2] (log1p and expm1: exact at
        // tiny kappa too).
        double oneMinusCos = 2 * u1;
        if (kappa > 0) oneMinusCos = std::min(2.0, -std::log1p((1 - u1) * std::expm1(-2 * kappa)) / kappa);
        const double cosTheta = 1 - oneMinusCos;
        const double sinTheta = std::sqrt(std::max(0.0, oneMinusCos * (2 - oneMinusCos)));
        return directionAround(mu, cosTheta, sinTheta, 2 * Pi * u2);
    }
};

} // namespace lt
