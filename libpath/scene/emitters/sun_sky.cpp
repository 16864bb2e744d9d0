#include "scene/emitters/sun_sky.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>

#include "math/bit_reversal.h"
#include "math/constants.h"
#include "util/error.h"
#include "math/frame.h"
#include "util/memory_budget.h"
#include "math/warp.h"
#include "scene/emitters/preetham_sun.h"

namespace lt {

namespace {

// The largest map lt bakes: 16384 x 8192 texels of three doubles is 3.2 GB.
constexpr int MaxResolution = 16384;

std::string degrees(double radians) {
    std::ostringstream os;
    os.precision(4);
    os << radToDeg(radians);
    return os.str();
}

void checkSettings(const DaylightSettings& s, bool withSky) {
    auto inRange = [](double v, double lo, double hi) { return v >= lo && v <= hi; }; // false for NaN
    if (!inRange(s.turbidity, 1, 10)) throw Error("turbidity must be in [1, 10]");
    if (!inRange(s.stretch, 1, 2)) throw Error("stretch must be in [1, 2]");
    if (withSky)
        for (int c = 0; c < 3; ++c)
            if (!inRange(s.albedo[c], 0, 1)) throw Error("albedo must be in [0, 1]");
    if (s.resolution < 2 || s.resolution > MaxResolution)
        throw Error("resolution must be in [2, " + std::to_string(MaxResolution) + "]");
    if (!(s.skyScale >= 0 && std::isfinite(s.skyScale)) || !(s.sunScale >= 0 && std::isfinite(s.sunScale)))
        throw Error("scale must be a finite number >= 0");
    if (!inRange(s.sunRadiusScale * SunAngularRadius, 0, Pi / 2))
        throw Error("sunRadiusScale must be in [0, " + std::to_string(int(Pi / 2 / SunAngularRadius)) +
                    "] (a sun disk within a hemisphere)");
    if (!(s.sun.zenith <= Pi / 2))
        throw Error("the sun is below the horizon (" + degrees(s.sun.zenith - Pi / 2) +
                    " degrees): the sky and sun models do not hold there");
}

// Van der Corput's radical inverse in base 2: with (i + 1/2) / n, the Hammersley points.
double radicalInverse2(uint32_t i) { return reverseBits(i) * 0x1p-32; }

// The sun as seen, radius scaled and direction stretched (Mitsuba sun.cpp configure), and the irradiance
// of the true disk (radiance times its solid angle), which a scaled disk keeps.
SkyAngles sunSeen(const DaylightSettings& s) { return {std::min(Pi, s.sun.zenith * s.stretch), s.sun.azimuth}; }
Spectrum sunIrradiance(const DaylightSettings& s) {
    const double oneMinusCos = 2 * std::pow(std::sin(SunAngularRadius / 2), 2);
    return preethamSunRadiance(s.sun.zenith, s.turbidity) * (s.sunScale * TwoPi * oneMinusCos);
}

// Rasterize the sun disk into the map: Hammersley directions uniform in its cone, each adding its share of
// the irradiance to the texel it falls in as radiance (share / the texel's solid angle), so the map's
// irradiance from the disk is exact at any resolution (Mitsuba sun.cpp does the same with sin(theta) of
// the sample in place of the texel's solid angle).
void rasterizeSun(const DaylightSettings& s, LatLongImage& map) {
    const double half = SunAngularRadius * s.sunRadiusScale / 2;
    const double oneMinusCos = 2 * std::sin(half) * std::sin(half);
    const double texels = double(map.width) * map.height;
    // Mitsuba's count, capped where a huge map and disk would take minutes (and outrun the 32-bit radical inverse).
    const size_t n = size_t(std::clamp(texels * 0.5 * oneMinusCos * 1000, 100.0, double(1 << 24)));
    const Spectrum share = sunIrradiance(s) / double(n);
    const Frame frame = Frame::fromNormal(skyDirection(sunSeen(s)));
    for (size_t i = 0; i < n; ++i) {
        const Vec2 u((i + 0.5) / double(n), radicalInverse2(uint32_t(i)));
        const auto [x, y] = latLongTexel(normalize(frame.toWorld(warp::squareToUniformConeNarrow(u, oneMinusCos))),
                                         map.width, map.height);
        const double texelSolidAngle =
            TwoPi / map.width * (std::cos(Pi * y / map.height) - std::cos(Pi * (y + 1) / map.height));
        map.pixels[size_t(y) * map.width + x] += share / texelSolidAngle;
    }
}

const DaylightSettings& checkedSky(const DaylightSettings& s) {
    checkSettings(s, true);
    return s;
}

double smoothStep(double x) {
    x = std::clamp(x, 0.0, 1.0);
    return x * x * (3 - 2 * x);
}

} // namespace

SkyDome::SkyDome(const DaylightSettings& settings)
    : settings_(checkedSky(settings)), model_(settings.turbidity, settings.albedo, Pi / 2 - settings.sun.zenith) {}

Spectrum SkyDome::radiance(const SkyAngles& view) const {
    double theta = view.zenith / settings_.stretch;
    if (std::cos(theta) <= 0) {
        if (!settings_.extend) return {};
        theta = Pi / 2 - 1e-4; // below the horizon the extended sky repeats the horizon, fading out
    }
    const SkyAngles& sun = settings_.sun;
    const double cosGamma = std::cos(theta) * std::cos(sun.zenith) +
                            std::sin(theta) * std::sin(sun.zenith) * std::cos(view.azimuth - sun.azimuth);
    Spectrum L = max(model_.radiance(theta, safeAcos(cosGamma)) / 106.856980, Spectrum(0.0));
    if (settings_.extend) L *= smoothStep(2 - 2 * view.zenith / Pi);
    return L * settings_.skyScale;
}

std::vector<std::unique_ptr<Emitter>> makeDaylightEmitters(const DaylightSettings& s, bool withSky, bool withSun,
                                                           const std::string& type) {
    checkSettings(s, withSky);
    const bool sunInMap = withSun && s.sunRadiusScale > 0;
    std::vector<std::unique_ptr<Emitter>> emitters;
    if (withSky || sunInMap) {
        LatLongImage map{s.resolution, s.resolution / 2, {}};
        // The map's texels and the envmap emitter's sampling distribution over them (weights, cdf, pmf).
        requireMemory(double(map.width) * double(map.height) * (sizeof(Spectrum) + 3 * sizeof(double)),
                      "a sky map of " + std::to_string(map.width) + "x" + std::to_string(map.height) + " texels");
        map.pixels.resize(size_t(map.width) * size_t(map.height));
        if (withSky) {
            const SkyDome dome(s);
            for (int y = 0; y < map.height; ++y)
                for (int x = 0; x < map.width; ++x)
                    map.pixels[size_t(y) * map.width + x] =
                        dome.radiance({(y + 0.5) * Pi / map.height, (x + 0.5) * TwoPi / map.width});
        }
        if (sunInMap) rasterizeSun(s, map);
        emitters.push_back(makeEnvmapEmitter(std::move(map), s.toWorld, type));
    }
    if (withSun && !sunInMap)
        emitters.push_back(
            makeDirectionalEmitter(-normalize(s.toWorld.vector(skyDirection(sunSeen(s)))), sunIrradiance(s)));
    return emitters;
}

} // namespace lt
