// Shapes built in code for the tests of the manifold machinery and HSLT.
#pragma once

#include <array>

#include "scene/shape.h"

namespace lt::test {

// An axis-aligned box [lo, hi] with outward normals, as a mesh.
inline Shape box(const Vec3& lo, const Vec3& hi) {
    TriangleMesh m;
    for (int i = 0; i < 8; ++i)
        m.positions.push_back(Vec3f(Vec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z)));
    const std::array<std::array<uint32_t, 4>, 6> faces{
        {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}}};
    for (const auto& f : faces) {
        m.triangles.push_back({f[0], f[1], f[2]});
        m.triangles.push_back({f[0], f[2], f[3]});
    }
    return Shape::triangles(std::move(m), false);
}

} // namespace lt::test
