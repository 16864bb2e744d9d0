// The Hosek-Wilkie sky model, RGB version: L. Hosek and A. Wilkie, "An Analytic Model for Full Spectral
// Sky-Dome Radiance", ACM TOG 31(4), SIGGRAPH 2012.
//
// The radiance of a clear sky in a view direction at zenith angle theta, at angle gamma from the sun, is the
// extended Perez formula (Eq. 9)
//   F(theta, gamma) = (1 + A e^(B / (cos theta + 0.01))) (C + D e^(E gamma) + F cos^2 gamma + G chi(H, gamma)
//                     + I cos^(1/2) theta),   chi(g, a) = (1 + cos^2 a) / (1 + g^2 - 2 g cos a)^(3/2),
// times the model's zenith radiance L_M (Eq. 8). Its nine parameters and L_M come from the fitted dataset
// (hosek_wilkie_data.h), for each channel: a quintic Bezier curve in (solar elevation / (pi/2))^(1/3),
// interpolated linearly in turbidity (integer steps 1 to 10) and in ground albedo (0 and 1) (Sec. 6).
#pragma once

#include <array>

#include "math/spectrum.h"

namespace lt {

class HosekWilkieSky {
public:
    // turbidity in [1, 10], albedo per channel in [0, 1], solarElevation in [0, pi/2] (above the horizon).
    HosekWilkieSky(double turbidity, const Spectrum& albedo, double solarElevation);

    // Radiance in the dataset's RGB units; theta in [0, pi/2], gamma in [0, pi].
    [[nodiscard]] Spectrum radiance(double theta, double gamma) const;

private:
    std::array<std::array<double, 9>, 3> parameters_{}; // per channel, in the dataset's order A..G I H
    std::array<double, 3> zenithRadiance_{};            // L_M per channel
};

} // namespace lt
