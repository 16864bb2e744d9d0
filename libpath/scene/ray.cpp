#include "scene/ray.h"

#include <bit>
#include <cmath>
#include <cstdint>

namespace lt {

namespace {

// Ray Tracing Gems ch. 6: 256 float ulps along the normal (listing 6-1's int_scale).
constexpr float IntScale = 256.0f;
// The floor, relative to the primitive's magnitude: 2^-18 is 32 float ulps of the largest coordinate,
// above the few ulps of error of Embree's float ray-triangle test (and of the float rounding of p).
constexpr double MagnitudeScale = 0x1.0p-18;

// std::nextafter(x, up ? +inf : -inf), inline: libm's call cost a few percent of path tracing (it runs for
// every component of both ends of every ray). Within a sign, the order of finite floats is that of their
// bit patterns, so one step is one unit of the pattern; zero and non-finite values take libm's answer.
float nextFloat(float x, bool up) {
    if (x == 0 || !std::isfinite(x)) return std::nextafter(x, up ? INFINITY : -INFINITY);
    return std::bit_cast<float>(std::bit_cast<int32_t>(x) + ((x > 0) == up ? 1 : -1));
}

float offsetComponent(double p, double n, double magnitude) {
    // A zero component of the normal (every component but one on axis-aligned walls) offsets by nothing:
    // below, byUlps is then float(p) and byMagnitude float(p + n x ...), no farther from p, so the latter
    // is returned (for signed zeros and non-finite inputs too).
    if (n == 0) return float(p + n * MagnitudeScale * magnitude);
    const float pf = float(p);
    const int32_t ofi = int32_t(IntScale * float(n));
    const float byUlps = std::bit_cast<float>(std::bit_cast<int32_t>(pf) + ((pf < 0) ? -ofi : ofi));
    float byMagnitude = float(p + n * MagnitudeScale * magnitude);
    // Round away from the surface so the float position keeps the full offset.
    byMagnitude = nextFloat(byMagnitude, n > 0);
    // Whichever goes farther along n (both move in the direction of n).
    return std::abs(double(byUlps) - p) > std::abs(double(byMagnitude) - p) ? byUlps : byMagnitude;
}

} // namespace

Vec3 offsetRayOrigin(const RayEndpoint& at, const Vec3& dir) {
    const Vec3 n = dot(at.ng, dir) < 0 ? -at.ng : at.ng;
    return {offsetComponent(at.p.x, n.x, at.magnitude), offsetComponent(at.p.y, n.y, at.magnitude),
            offsetComponent(at.p.z, n.z, at.magnitude)};
}

Ray spawnRay(const RayEndpoint& from, const Vec3& dir) {
    Ray r;
    r.o = lengthSquared(from.ng) > 0 ? offsetRayOrigin(from, dir) : from.p;
    r.d = dir;
    return r;
}

Ray spawnRayTo(const RayEndpoint& from, const RayEndpoint& to) {
    const Vec3 d0 = to.p - from.p;
    const Vec3 o = lengthSquared(from.ng) > 0 ? offsetRayOrigin(from, d0) : from.p;
    const Vec3 e = lengthSquared(to.ng) > 0 ? offsetRayOrigin(to, -d0) : to.p;
    Ray r;
    r.o = o;
    const Vec3 d = e - o;
    const double dist = length(d);
    r.d = d / dist;
    // The far end is itself offset off its surface; the factor only absorbs the float rounding of tfar.
    r.tmax = dist * (1.0 - 1e-6);
    return r;
}

} // namespace lt
