// RGB spectra. lt renders in linear sRGB (Rec. 709 primaries), as Mitsuba 0.5 does in RGB mode; spectra
// given as wavelength:value lists are converted once, at load time (see spectrum.cpp).
#pragma once

#include <functional>
#include <span>
#include <utility>

#include "math/vec.h"

namespace lt {

struct Spectrum {
    double r = 0, g = 0, b = 0;

    constexpr Spectrum() = default;
    constexpr explicit Spectrum(double v) : r(v), g(v), b(v) {}
    constexpr Spectrum(double r_, double g_, double b_) : r(r_), g(g_), b(b_) {}

    constexpr double operator[](int i) const { return i == 0 ? r : (i == 1 ? g : b); }
    constexpr double& operator[](int i) { return i == 0 ? r : (i == 1 ? g : b); }
    constexpr Spectrum operator+(const Spectrum& o) const { return {r + o.r, g + o.g, b + o.b}; }
    constexpr Spectrum operator-(const Spectrum& o) const { return {r - o.r, g - o.g, b - o.b}; }
    constexpr Spectrum operator*(const Spectrum& o) const { return {r * o.r, g * o.g, b * o.b}; }
    constexpr Spectrum operator/(const Spectrum& o) const { return {r / o.r, g / o.g, b / o.b}; }
    constexpr Spectrum operator*(double s) const { return {r * s, g * s, b * s}; }
    constexpr Spectrum operator/(double s) const { return {r / s, g / s, b / s}; }
    constexpr Spectrum& operator+=(const Spectrum& o) { r += o.r; g += o.g; b += o.b; return *this; }
    constexpr Spectrum& operator*=(const Spectrum& o) { r *= o.r; g *= o.g; b *= o.b; return *this; }
    constexpr Spectrum& operator*=(double s) { r *= s; g *= s; b *= s; return *this; }
    constexpr Spectrum& operator/=(double s) { r /= s; g /= s; b /= s; return *this; }
    constexpr bool operator==(const Spectrum&) const = default;

    [[nodiscard]] constexpr bool isBlack() const { return r == 0 && g == 0 && b == 0; }
    [[nodiscard]] constexpr double maxValue() const { return std::max(r, std::max(g, b)); }
    [[nodiscard]] constexpr double average() const { return (r + g + b) / 3.0; }
    // Rec. 709 luminance: the scalar target f* of the Markov chains (SURVEY Eq. 16).
    [[nodiscard]] constexpr double luminance() const { return 0.212671 * r + 0.715160 * g + 0.072169 * b; }
    [[nodiscard]] bool isFinite() const { return std::isfinite(r) && std::isfinite(g) && std::isfinite(b); }
};

constexpr Spectrum operator*(double s, const Spectrum& v) { return v * s; }
inline Spectrum sqrt(const Spectrum& v) { return {std::sqrt(v.r), std::sqrt(v.g), std::sqrt(v.b)}; }
inline Spectrum exp(const Spectrum& v) { return {std::exp(v.r), std::exp(v.g), std::exp(v.b)}; }
inline Spectrum max(const Spectrum& a, const Spectrum& b) {
    return {std::max(a.r, b.r), std::max(a.g, b.g), std::max(a.b, b.b)};
}

// Piecewise-linear interpolation of (nm, value) samples in ascending order. Beyond the ends: the end values
// (Clamp; Mitsuba's reading of a <spectrum> list) or zero (Zero; Mitsuba's InterpolatedSpectrum reading a
// tabulated quantity, such as the sun model's).
enum class BeyondSamples { Clamp, Zero };
double interpolateSamples(std::span<const std::pair<double, double>> samples, double nm, BeyondSamples beyond);

// CIE 1931 XYZ of a spectrum given as a function of the wavelength in nm, integrated over 360-830 nm and
// scaled so that the constant spectrum 1 has Y = 1 (Mitsuba's Spectrum::fromContinuousSpectrum in RGB mode).
Vec3 spectrumToXyz(const std::function<double(double)>& value);
// Linear sRGB (Rec. 709 primaries, D65) of CIE XYZ.
Spectrum xyzToRgb(const Vec3& xyz);

// Convert a sampled spectrum (wavelengths in nm, ascending, with values) to linear sRGB: integrate
// against the CIE 1931 observer, XYZ -> sRGB, and white-balance so that a constant spectrum c maps to
// RGB (c, c, c). Throws lt::Error if the samples are not ascending or fewer than one.
Spectrum spectrumToRgb(std::span<const std::pair<double, double>> samples);

} // namespace lt
