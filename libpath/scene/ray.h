// Rays and the robust spawning of secondary rays.
#pragma once

#include <limits>

#include "math/vec.h"

namespace lt {

struct Ray {
    Vec3 o, d;
    double tmin = 0;
    double tmax = std::numeric_limits<double>::infinity();
};

// The parameter t at which the line o + t d meets the plane through p with normal n (any sign; not finite
// when the line runs parallel to the plane). The one ray-plane intersection of the walks and their kernels.
[[nodiscard]] inline double planeCrossing(const Vec3& o, const Vec3& d, const Vec3& p, const Vec3& n) {
    return dot(p - o, n) / dot(d, n);
}

// Where a ray leaves from or ends: a position, its geometric normal (zero for points not on a surface,
// such as a pinhole or a point light), and the magnitude (largest absolute coordinate) of the primitive
// it lies on, which bounds the float error of Embree's intersection test there.
struct RayEndpoint {
    Vec3 p, ng;
    double magnitude = 0;
};

// Move a surface point off its surface, to the side of ng that dir points into, so that a ray leaving
// from it does not hit the same surface again. Embree intersects in single precision, so the offset is
// made in float ulps of the position (Waechter and Binder 2019, "A Fast and Robust Method for Avoiding
// Self-Intersection", Ray Tracing Gems ch. 6), with their fixed near-origin epsilon replaced by a floor
// proportional to the primitive's magnitude: a point near the origin on a large triangle still clears
// Embree's error, and nothing depends on the scene's absolute scale (tested from 1e-3 to 1e5).
Vec3 offsetRayOrigin(const RayEndpoint& at, const Vec3& dir);

// A ray leaving a surface point in direction dir (unit).
Ray spawnRay(const RayEndpoint& from, const Vec3& dir);
// A shadow ray between two points, each end offset from its surface; it stops short of the far end.
Ray spawnRayTo(const RayEndpoint& from, const RayEndpoint& to);

} // namespace lt
