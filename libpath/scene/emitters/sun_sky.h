// Mitsuba 0.6's daylight emitters `sky`, `sun` and `sunsky`, built the way Mitsuba builds them: the sky
// model (hosek_wilkie_sky.h) and the sun disk (preetham_sun.h) are baked into a lat-long environment map of
// resolution x resolution/2 texels (lat_long.h), rendered by lt's envmap emitter; a sun of radius scale 0
// is a directional emitter instead.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "math/constants.h"
#include "math/spectrum.h"
#include "math/transform.h"
#include "scene/emitter.h"
#include "scene/emitters/hosek_wilkie_sky.h"
#include "scene/emitters/lat_long.h"

namespace lt {

struct DaylightSettings {
    SkyAngles sun;        // the sun's position in the emitters' local frame (toWorld^-1 applied)
    double turbidity = 3; // [1, 10]
    Spectrum albedo{0.2}; // ground albedo per channel, [0, 1] (sky)
    double stretch = 1;   // [1, 2]: the sky's zenith angles divided by it, the sun's multiplied
    bool extend = false;  // continue the sky below the horizon, fading out (sky)
    int resolution = 512; // map width; height resolution / 2
    double skyScale = 1, sunScale = 1;
    double sunRadiusScale = 1; // the sun disk's radius, as a multiple of the true one (0: directional)
    Transform toWorld;
};

// The true sun's angular radius (0.5358 / 2 degrees, Mitsuba's sun.cpp) and the solid angle of its disk.
inline constexpr double SunAngularRadius = degToRad(0.5358 / 2);

// The emitters of `sky` (withSky), `sun` (withSun) or `sunsky` (both, one map): one envmap, plus a
// directional emitter when the sun's radius scale is 0. Throws lt::Error for settings out of range or a sun
// below the horizon (the sky model and the sun's optical mass do not hold there).
std::vector<std::unique_ptr<Emitter>> makeDaylightEmitters(const DaylightSettings& settings, bool withSky, bool withSun,
                                                           const std::string& type);

// The sky's radiance by local direction, before baking (Mitsuba sky.cpp getSkyRadiance).
class SkyDome {
public:
    // Throws lt::Error for a sun below the horizon.
    explicit SkyDome(const DaylightSettings& settings);
    // The model's RGB over 106.856980 (the sum of the CIE Y samples that Mitsuba divides the dataset's
    // units by), negative values clamped, times skyScale; zero below the horizon unless extended.
    [[nodiscard]] Spectrum radiance(const SkyAngles& view) const;

private:
    DaylightSettings settings_;
    HosekWilkieSky model_;
};

} // namespace lt
