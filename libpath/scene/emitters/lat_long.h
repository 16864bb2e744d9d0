// The latitude-longitude parametrization of the sky that Mitsuba's envmap, sky, sun and sunsky share, in
// the emitter's local frame (+y up, Mitsuba's envmap.cpp and sunmodel.h toSphere/fromSphere): azimuth phi
// and zenith angle theta give v = (sin phi sin theta, cos theta, -cos phi sin theta). An image of width W
// and height H holds azimuth 2 pi u in its columns (u = x / W) and zenith angle pi t in its rows (t = y / H,
// row 0 at the zenith).
#pragma once

#include <cmath>

#include "math/constants.h"
#include "math/numeric.h"
#include "math/vec.h"

namespace lt {

struct SkyAngles {
    double zenith = 0;  // theta in [0, pi]
    double azimuth = 0; // phi in [0, 2 pi)
};

inline Vec3 skyDirection(const SkyAngles& a) {
    const double sinTheta = std::sin(a.zenith);
    return {std::sin(a.azimuth) * sinTheta, std::cos(a.zenith), -std::cos(a.azimuth) * sinTheta};
}

// Of a unit local direction.
inline SkyAngles skyAngles(const Vec3& v) {
    double phi = std::atan2(v.x, -v.z);
    if (phi < 0) phi += TwoPi;
    return {safeAcos(v.y), phi};
}

} // namespace lt
