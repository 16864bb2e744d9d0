#include "scene/emitters/preetham_sun.h"

#include <array>
#include <cmath>
#include <span>
#include <utility>

#include "math/constants.h"

namespace lt {

namespace {

using Table = std::span<const std::pair<double, double>>; // (nm, value), ascending

// Ozone absorption coefficient k_o (1/cm), Iqbal p. 127 (Preetham et al. Table 2).
constexpr std::pair<double, double> OzoneAbsorption[] = {
    {300, 10.0},  {305, 4.8},   {310, 2.7},   {315, 1.35},  {320, 0.8},   {325, 0.380}, {330, 0.160}, {335, 0.075},
    {340, 0.04},  {345, 0.019}, {350, 0.007}, {355, 0.0},   {445, 0.003}, {450, 0.003}, {455, 0.004}, {460, 0.006},
    {465, 0.008}, {470, 0.009}, {475, 0.012}, {480, 0.014}, {485, 0.017}, {490, 0.021}, {495, 0.025}, {500, 0.03},
    {505, 0.035}, {510, 0.04},  {515, 0.045}, {520, 0.048}, {525, 0.057}, {530, 0.063}, {535, 0.07},  {540, 0.075},
    {545, 0.08},  {550, 0.085}, {555, 0.095}, {560, 0.103}, {565, 0.110}, {570, 0.12},  {575, 0.122}, {580, 0.12},
    {585, 0.118}, {590, 0.115}, {595, 0.12},  {600, 0.125}, {605, 0.130}, {610, 0.12},  {620, 0.105}, {630, 0.09},
    {640, 0.079}, {650, 0.067}, {660, 0.057}, {670, 0.048}, {680, 0.036}, {690, 0.028}, {700, 0.023}, {710, 0.018},
    {720, 0.014}, {730, 0.011}, {740, 0.010}, {750, 0.009}, {760, 0.007}, {770, 0.004}, {780, 0.0},   {790, 0.0}};
// Mixed gases absorption coefficient k_g, Iqbal p. 130.
constexpr std::pair<double, double> GasAbsorption[] = {{759, 0}, {760, 3.0}, {770, 0.210}, {771, 0}};
// Water vapour absorption coefficient k_wa, Iqbal p. 130.
constexpr std::pair<double, double> WaterAbsorption[] = {
    {689, 0},     {690, 0.016},   {700, 0.024},   {710, 0.0125}, {720, 1.0},    {730, 0.87}, {740, 0.061},
    {750, 0.001}, {760, 0.00001}, {770, 0.00001}, {780, 0.0006}, {790, 0.0175}, {800, 0.036}};
// Extraterrestrial solar spectral radiance (W / (m^2 sr um)) of Preetham et al. Table 2.
constexpr std::pair<double, double> SolarRadiance[] = {
    {380, 16559.0}, {390, 16233.7}, {400, 21127.5}, {410, 25888.2}, {420, 25829.1}, {430, 24232.3}, {440, 26760.5},
    {450, 29658.3}, {460, 30545.4}, {470, 30057.5}, {480, 30663.7}, {490, 28830.4}, {500, 28712.1}, {510, 27825.0},
    {520, 27100.6}, {530, 27233.6}, {540, 26361.3}, {550, 25503.8}, {560, 25060.2}, {570, 25311.6}, {580, 25355.9},
    {590, 25134.2}, {600, 24631.5}, {610, 24173.2}, {620, 23685.3}, {630, 23212.1}, {640, 22827.7}, {650, 22339.8},
    {660, 21970.2}, {670, 21526.7}, {680, 21097.9}, {690, 20728.3}, {700, 20240.4}, {710, 19870.8}, {720, 19427.2},
    {730, 19072.4}, {740, 18628.9}, {750, 18259.2}};

} // namespace

Spectrum preethamSunRadiance(double zenith, double turbidity) {
    // Aerosol amount (Angstrom's beta) from turbidity, and the relative optical mass of Kasten and Young
    // (Preetham et al. Appendix A.2; the zenith angle in degrees inside the power).
    const double beta = 0.04608365822050 * turbidity - 0.04586025928522;
    const double mass = 1.0 / (std::cos(zenith) + 0.15 * std::pow(93.885 - radToDeg(zenith), -1.253));
    constexpr double alpha = 1.3;  // ratio of small to large aerosol particles
    constexpr double ozone = 0.35; // ozone column, cm (NTP)
    constexpr double water = 2.0;  // precipitable water vapour, cm
    // Tabulated quantities are zero where they are not tabulated (as Mitsuba's InterpolatedSpectrum reads them).
    const auto table = [](std::span<const std::pair<double, double>> t, double nm) {
        return interpolateSamples(t, nm, BeyondSamples::Zero);
    };
    // The attenuated spectrum every 5 nm over 350-800 nm, read piecewise linearly in between.
    std::array<std::pair<double, double>, 91> sun;
    for (int i = 0; i < 91; ++i) {
        const double nm = 350 + 5 * i, um = nm / 1000;
        const double kg = table(GasAbsorption, nm), kwa = table(WaterAbsorption, nm);
        const double rayleigh = std::exp(-mass * 0.008735 * std::pow(um, -4.08));
        const double aerosol = std::exp(-mass * beta * std::pow(um, -alpha));
        const double ozoneT = std::exp(-mass * table(OzoneAbsorption, nm) * ozone);
        const double gases = std::exp(-1.41 * kg * mass / std::pow(1 + 118.93 * kg * mass, 0.45));
        const double vapour = std::exp(-0.2385 * kwa * water * mass / std::pow(1 + 20.07 * kwa * water * mass, 0.45));
        sun[i] = {nm, table(SolarRadiance, nm) * rayleigh * aerosol * ozoneT * gases * vapour};
    }
    const Spectrum rgb = xyzToRgb(spectrumToXyz([&](double nm) { return table(sun, nm); }));
    return max(rgb, Spectrum(0.0));
}

} // namespace lt
