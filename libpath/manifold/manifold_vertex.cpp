#include "manifold/manifold_vertex.h"

#include <cmath>

#include "manifold/block_tridiagonal.h"

namespace lt {

std::optional<ManifoldVertex> manifoldVertex(const SurfaceInteraction& si) {
    // A bump map's normal carries the smooth surface's derivatives (scene/bump_frame.h): the determinants a
    // walk's T(x -> y) rests on would be wrong. No chain holds such a vertex, in x or in y, so the walks that
    // would need one fail both ways and the chains stay unbiased (other mutations move those paths).
    if (si.bumped) return std::nullopt;
    // Gram-Schmidt: u = a dp/du, v = (dp/dv - (dp/dv.u) a dp/du) / |...|; the normal derivatives follow
    // the same linear map (ME footnote 2).
    const double lu = length(si.dpdu);
    if (!(lu > 0) || !std::isfinite(lu)) return std::nullopt;
    const double a = 1 / lu;
    const Vec3 u = si.dpdu * a;
    const double proj = dot(si.dpdv, u);
    const Vec3 vRest = si.dpdv - u * proj;
    const double lv = length(vRest);
    if (!(lv > 1e-12 * length(si.dpdv)) || !std::isfinite(lv)) return std::nullopt;
    ManifoldVertex v;
    v.p = si.p;
    v.ng = si.ng;
    v.n = si.shading.n;
    v.dpdu = u;
    v.dpdv = vRest / lv;
    v.dndu = si.dndu * a;
    v.dndv = (si.dndv - si.dndu * (proj * a)) / lv;
    // The frame generators: the world axes other than the geometric normal's dominant one.
    const Vec3 ng = si.ng;
    const int m = std::abs(ng.x) >= std::abs(ng.y) && std::abs(ng.x) >= std::abs(ng.z) ? 0
                  : std::abs(ng.y) >= std::abs(ng.z)                                   ? 1
                                                                                       : 2;
    const Vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    v.frameU = axes[(m + 1) % 3];
    v.frameV = axes[(m + 2) % 3];
    v.shape = si.shape;
    v.prim = si.prim;
    v.coords = si.coords;
    v.magnitude = si.magnitude;
    return v;
}

ManifoldVertex planeVertex(const Vec3& p, const Vec3& normal) {
    const Frame f = Frame::fromNormal(normal);
    ManifoldVertex v;
    v.p = p;
    v.ng = v.n = normal;
    v.dpdu = v.frameU = f.s;
    v.dpdv = v.frameV = f.t;
    return v;
}

ManifoldVertex pointVertex(const Vec3& p, const Vec3& axis) {
    ManifoldVertex v = planeVertex(p, axis);
    v.ng = Vec3();
    return v;
}

ManifoldVertex infiniteVertex(const Vec3& far, const Vec3& toward) {
    ManifoldVertex v = pointVertex(far, toward);
    v.atInfinity = true;
    return v;
}

std::optional<Vec3> microfacetNormal(const ManifoldVertex& v, const Vec2& offset) {
    const Vec3 s = v.s(), t = v.t();
    const Mat2 gram{{{{dot(s, s), dot(s, t)}, {dot(s, t), dot(t, t)}}}};
    const auto inv = gram.inverse();
    if (!inv) return std::nullopt;
    const auto ab = *inv * std::array<double, 2>{offset.x, offset.y};
    const Vec3 w = s * ab[0] + t * ab[1];
    const double w2 = lengthSquared(w);
    if (!(w2 < 1)) return std::nullopt;
    return w + v.n * std::sqrt(1 - w2);
}

} // namespace lt
