#include "math/spectrum.h"

#include <cmath>

#include "util/error.h"

namespace lt {

namespace {

// CIE 1931 2-degree colour matching functions, multi-lobe piecewise Gaussian fit of Wyman, Sloan and
// Shirley 2013, "Simple Analytic Approximations to the CIE XYZ Color Matching Functions" (Eq. 2-4).
// Accurate to well below the precision that matters for an RGB renderer, and no table to maintain.
double gaussianPiecewise(double x, double mu, double s1, double s2) {
    const double t = (x - mu) / (x < mu ? s1 : s2);
    return std::exp(-0.5 * t * t);
}
Vec3 cieXyz(double nm) {
    const double x = 1.056 * gaussianPiecewise(nm, 599.8, 37.9, 31.0) + 0.362 * gaussianPiecewise(nm, 442.0, 16.0, 26.7) -
                     0.065 * gaussianPiecewise(nm, 501.1, 20.4, 26.2);
    const double y = 0.821 * gaussianPiecewise(nm, 568.8, 46.9, 40.5) + 0.286 * gaussianPiecewise(nm, 530.9, 16.3, 31.1);
    const double z = 1.217 * gaussianPiecewise(nm, 437.0, 11.8, 36.0) + 0.681 * gaussianPiecewise(nm, 459.0, 26.0, 13.8);
    return {x, y, z};
}

// The sum over 360-830 nm, 1 nm apart, of the colour matching functions times the spectrum.
Vec3 integrateXyz(const std::function<double(double)>& value) {
    Vec3 xyz;
    for (double nm = 360.0; nm <= 830.0; nm += 1.0)
        xyz += cieXyz(nm) * value(nm);
    return xyz;
}
} // namespace

double interpolateSamples(std::span<const std::pair<double, double>> s, double nm, BeyondSamples beyond) {
    if (nm < s.front().first || nm > s.back().first) {
        if (beyond == BeyondSamples::Zero) return 0;
        return nm < s.front().first ? s.front().second : s.back().second;
    }
    for (size_t i = 1; i < s.size(); ++i)
        if (nm <= s[i].first) {
            const double t = (nm - s[i - 1].first) / (s[i].first - s[i - 1].first);
            return s[i - 1].second * (1 - t) + s[i].second * t;
        }
    return s.back().second;
}

Vec3 spectrumToXyz(const std::function<double(double)>& value) {
    static const double yIntegral = integrateXyz([](double) { return 1.0; }).y;
    return integrateXyz(value) / yIntegral;
}

Spectrum xyzToRgb(const Vec3& c) {
    return {3.240479 * c.x - 1.537150 * c.y - 0.498535 * c.z, -0.969256 * c.x + 1.875991 * c.y + 0.041556 * c.z,
            0.055648 * c.x - 0.204043 * c.y + 1.057311 * c.z};
}

Spectrum spectrumToRgb(std::span<const std::pair<double, double>> samples) {
    if (samples.empty()) throw Error("spectrum has no samples");
    for (size_t i = 1; i < samples.size(); ++i)
        if (!(samples[i].first > samples[i - 1].first))
            throw Error("spectrum wavelengths must be strictly ascending");
    // White balance on the raw integrals (the normalization of spectrumToXyz would cancel).
    static const Spectrum white = xyzToRgb(integrateXyz([](double) { return 1.0; }));
    return xyzToRgb(integrateXyz([&](double nm) { return interpolateSamples(samples, nm, BeyondSamples::Clamp); })) /
           white;
}

} // namespace lt
