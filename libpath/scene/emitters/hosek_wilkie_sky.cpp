#include "scene/emitters/hosek_wilkie_sky.h"

#include <algorithm>
#include <cmath>

#include "math/constants.h"
#include "scene/emitters/hosek_wilkie_data.h"

namespace lt {

namespace {

// The quintic Bezier curve through six control points `stride` apart, at x in [0, 1].
double bezier5(const double* control, int stride, double x) {
    const double y = 1 - x;
    const double basis[6] = {y * y * y * y * y,      5 * y * y * y * y * x, 10 * y * y * y * x * x,
                             10 * y * y * x * x * x, 5 * y * x * x * x * x, x * x * x * x * x};
    double sum = 0;
    for (int k = 0; k < 6; ++k)
        sum += basis[k] * control[k * stride];
    return sum;
}

// A dataset quantity (one of `count` interleaved per control point) at the given turbidity, albedo and
// elevation: the curves of the two bracketing integer turbidities and of albedo 0 and 1, blended linearly.
double blend(const double* data, int count, int index, double turbidity, double albedo, double x) {
    const int low = std::clamp(int(turbidity), 1, 10);
    const double rest = turbidity - low;
    const int curve = 6 * count;      // one turbidity's control points
    const int albedoOne = 10 * curve; // where albedo 1 starts
    auto at = [&](int t, int a) { return bezier5(data + a * albedoOne + (t - 1) * curve + index, count, x); };
    double value = (1 - albedo) * (1 - rest) * at(low, 0) + albedo * (1 - rest) * at(low, 1);
    if (low < 10) value += (1 - albedo) * rest * at(low + 1, 0) + albedo * rest * at(low + 1, 1);
    return value;
}

} // namespace

HosekWilkieSky::HosekWilkieSky(double turbidity, const Spectrum& albedo, double solarElevation) {
    const double x = std::cbrt(std::clamp(solarElevation / (Pi / 2), 0.0, 1.0));
    for (int c = 0; c < 3; ++c) {
        for (int i = 0; i < 9; ++i)
            parameters_[c][i] = blend(hosek_wilkie::RgbConfiguration[c], 9, i, turbidity, albedo[c], x);
        zenithRadiance_[c] = blend(hosek_wilkie::RgbRadiance[c], 1, 0, turbidity, albedo[c], x);
    }
}

Spectrum HosekWilkieSky::radiance(double theta, double gamma) const {
    const double cosTheta = std::cos(theta), cosGamma = std::cos(gamma);
    Spectrum L;
    for (int c = 0; c < 3; ++c) {
        const auto& p = parameters_[c];
        const double A = p[0], B = p[1], C = p[2], D = p[3], E = p[4], F = p[5], G = p[6], I = p[7], H = p[8];
        const double chi = (1 + cosGamma * cosGamma) / std::pow(1 + H * H - 2 * H * cosGamma, 1.5);
        L[c] =
            (1 + A * std::exp(B / (cosTheta + 0.01))) *
            (C + D * std::exp(E * gamma) + F * cosGamma * cosGamma + G * chi + I * std::sqrt(std::max(0.0, cosTheta))) *
            zenithRadiance_[c];
    }
    return L;
}

} // namespace lt
