// Robust scalar helpers: clamped square roots and arc functions, so that round-off just outside a
// domain never produces NaN (the project promise: no NaN or Inf reaches an output).
#pragma once

#include <algorithm>
#include <cmath>

namespace lt {

inline double safeSqrt(double x) { return std::sqrt(std::max(0.0, x)); }
inline double safeAcos(double x) { return std::acos(std::clamp(x, -1.0, 1.0)); }
inline double safeAsin(double x) { return std::asin(std::clamp(x, -1.0, 1.0)); }
template <class T> constexpr T sqr(T x) { return x * x; }

// Solve a x^2 + b x + c = 0 in double with the numerically stable formulation (no cancellation);
// returns false when there is no real root. t0 <= t1.
inline bool solveQuadratic(double a, double b, double c, double& t0, double& t1) {
    if (a == 0) {
        if (b == 0) return false;
        t0 = t1 = -c / b;
        return true;
    }
    const double disc = b * b - 4 * a * c;
    if (disc < 0) return false;
    const double root = std::sqrt(disc);
    const double q = b < 0 ? -0.5 * (b - root) : -0.5 * (b + root);
    t0 = q / a;
    t1 = q != 0 ? c / q : t0;
    if (t0 > t1) std::swap(t0, t1);
    return true;
}

} // namespace lt
