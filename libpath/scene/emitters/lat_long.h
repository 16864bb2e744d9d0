// The latitude-longitude parametrization of the sky that Mitsuba's envmap, sky, sun and sunsky share, in
// the emitter's local frame (+y up, Mitsuba's envmap.cpp and sunmodel.h toSphere/fromSphere): azimuth phi
// and zenith angle theta give v = (sin phi sin theta, cos theta, -cos phi sin theta). An image of width W
// and height H holds azimuth 2 pi u in its columns (u = x / W) and zenith angle pi t in its rows (t = y / H,
// row 0 at the zenith).
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>

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

// The image coordinates (u, t) in [0, 1]^2 of a unit local direction: u = phi / 2 pi, t = theta / pi.
inline Vec2 latLongCoordinates(const Vec3& v) {
    double u = std::atan2(v.x, -v.z) * InvTwoPi;
    if (u < 0) u += 1;
    return {u, safeAcos(v.y) * InvPi};
}

// The texel (column, row) of an image of width w and height h that a unit local direction falls in.
inline std::pair<int, int> latLongTexel(const Vec3& v, int w, int h) {
    const Vec2 uv = latLongCoordinates(v);
    return {std::clamp(int(uv.x * w), 0, w - 1), std::clamp(int(uv.y * h), 0, h - 1)};
}

// Of a unit local direction.
inline SkyAngles skyAngles(const Vec3& v) {
    const Vec2 uv = latLongCoordinates(v);
    return {Pi * uv.y, TwoPi * uv.x};
}

} // namespace lt
