// The local differential geometry at a surface point: everything the BSDFs, the path records and the
// manifold walks need.
#pragma once

#include <cstdint>

#include "math/frame.h"
#include "math/vec.h"
#include "scene/ray.h"

namespace lt {

struct SurfaceInteraction {
    Vec3 p;                 // position (double: recomputed from the primitive, not from the float ray)
    Vec3 ng;                // unit geometric normal (after flipNormals)
    Frame shading;          // shading frame: n = shading normal, s along dp/du projected into the tangent plane
    Vec2 uv;                // surface parameterization
    Vec3 dpdu, dpdv;        // position derivatives
    Vec3 dndu, dndv;        // derivatives of the (normalized) shading normal, consistent with shading.n
    int shape = -1;         // index into Scene::shapes
    uint32_t prim = 0;      // triangle index (0 for analytic shapes)
    Vec2 coords;            // barycentrics (b1, b2) for triangles; uv for analytic shapes
    double t = 0;           // ray distance when produced by an intersection
    double magnitude = 0;   // largest absolute coordinate of the primitive (bounds Embree's float error)
    bool bumped = false;    // the shading frame is a bump map's; dndu, dndv are still the smooth surface's

    [[nodiscard]] RayEndpoint endpoint() const { return {p, ng, magnitude}; }
};

} // namespace lt
