#include "scene/shape.h"

#include <cmath>
#include <tuple>
#include <utility>

#include "math/constants.h"
#include "util/error.h"
#include "math/numeric.h"
#include "math/warp.h"
#include "scene/bump_frame.h"

namespace lt {

namespace {

Vec3 toD(const Vec3f& v) { return Vec3(v); }

// A triangle's geometric normal is turned to its shading normals' side once for the whole triangle when
// every vertex normal (unit) has a cosine beyond SideMargin on one side, and the coordinates are within
// InsideMargin of the triangle: then the interpolated normal's cosine is at least
// SideMargin - 2 InsideMargin (1 + 1e-3) > 0, and the per-point rule gives the same side.
constexpr double SideMargin = 1e-3;
constexpr double InsideMargin = 1e-4;

// The unit normal of a triangle's winding (p1 - p0) x (p2 - p0), before any turn to its shading normals.
Vec3 windingNormal(const Vec3& p0, const Vec3& p1, const Vec3& p2) { return normalize(cross(p1 - p0, p2 - p0)); }

// A chart (u, v) that is linear over a triangle, given by its values at the three vertices. The
// derivatives of any other quantity linear over the triangle (position, interpolated normal) follow
// from its vertex values by Cramer's rule on the edges to vertex 2 (pbrt-v3 Triangle::Intersect).
struct TriangleChart {
    Vec2 d02, d12; // c_0 - c_2, c_1 - c_2
    double det = 0;

    TriangleChart(const Vec2& c0, const Vec2& c1, const Vec2& c2)
        : d02(c0 - c2), d12(c1 - c2), det(d02.x * d12.y - d02.y * d12.x) {}

    // d/du, d/dv of the field with vertex values f0, f1, f2.
    [[nodiscard]] std::pair<Vec3, Vec3> derivatives(const Vec3& f0, const Vec3& f1, const Vec3& f2) const {
        const Vec3 f02 = f0 - f2, f12 = f1 - f2;
        return {(f02 * d12.y - f12 * d02.y) / det, (f12 * d02.x - f02 * d12.x) / det};
    }
};

} // namespace

Shape Shape::triangles(TriangleMesh mesh, bool flipNormals) {
    Shape s;
    s.kind_ = Kind::Triangles;
    s.mesh_ = std::move(mesh);
    s.flip_ = flipNormals;
    s.finishTriangles();
    return s;
}

void Shape::finishTriangles() {
    const size_t count = mesh_.triangles.size();
    std::vector<double> areas(count);
    geometricNormals_.resize(count);
    if (!mesh_.normals.empty()) {
        sideVaries_.assign(count, false);
        normalsVary_.assign(count, false);
    }
    for (size_t i = 0; i < count; ++i) {
        const auto& t = mesh_.triangles[i];
        const Vec3 p0 = toD(mesh_.positions[t[0]]), p1 = toD(mesh_.positions[t[1]]), p2 = toD(mesh_.positions[t[2]]);
        areas[i] = 0.5 * length(cross(p1 - p0, p2 - p0));
        Vec3 ng = windingNormal(p0, p1, p2);
        if (!mesh_.normals.empty()) {
            // The geometric normal follows the shading normal's side (pbrt-v3 Triangle): mesh files are
            // often wound inconsistently, their normals rarely are. Where all three vertex normals are unit
            // and on one side by more than SideMargin, so is every interpolation of them at coordinates
            // within InsideMargin of the triangle (trianglePoint): the side is the triangle's.
            bool allAbove = true, allBelow = true;
            for (const uint32_t v : t) {
                const Vec3 n = toD(mesh_.normals[v]);
                const bool unit = std::abs(lengthSquared(n) - 1) < 1e-3;
                const double side = dot(ng, n);
                allAbove = allAbove && unit && side > SideMargin; // false for NaN as well
                allBelow = allBelow && unit && side < -SideMargin;
            }
            if (allBelow)
                ng = -ng;
            else if (!allAbove)
                sideVaries_[i] = true;
            const Vec3f& n0 = mesh_.normals[t[0]];
            normalsVary_[i] = !(n0 == mesh_.normals[t[1]] && n0 == mesh_.normals[t[2]]);
        }
        geometricNormals_[i] = flip_ ? -ng : ng;
    }
    triangleAreas_ = DiscreteDistribution(areas);
    area_ = triangleAreas_.total();
    for (const auto& p : mesh_.positions) bounds_.expand(toD(p));
}

Shape Shape::sphere(const Vec3& center, double radius, bool flipNormals) {
    if (!(radius > 0) || !std::isfinite(radius)) throw Error("sphere radius must be positive and finite");
    if (!isFinite(center)) throw Error("sphere center is not finite");
    Shape s;
    s.kind_ = Kind::Sphere;
    s.center_ = center;
    s.radius_ = radius;
    s.flip_ = flipNormals;
    s.area_ = 4 * Pi * radius * radius;
    s.bounds_.expand(center - Vec3(radius, radius, radius));
    s.bounds_.expand(center + Vec3(radius, radius, radius));
    return s;
}

Shape Shape::disk(const Transform& toWorld, bool flipNormals) {
    Shape s;
    s.kind_ = Kind::Disk;
    s.toWorld_ = toWorld;
    s.flip_ = flipNormals;
    // An affine map scales every area in a plane by the same factor: |dp/dx x dp/dy|.
    s.area_ = Pi * length(cross(toWorld.vector({1, 0, 0}), toWorld.vector({0, 1, 0})));
    if (!(s.area_ > 0)) throw Error("disk transform is degenerate");
    for (int i = 0; i < 4; ++i) {
        const double a = i * Pi / 2;
        s.bounds_.expand(toWorld.point({std::cos(a), std::sin(a), 0}));
    }
    // The four axis points bound an ellipse only loosely: use the exact extent of the image of the
    // unit circle, center +- sqrt(sum of squared in-plane columns) per axis.
    const Vec3 c = toWorld.point({0, 0, 0}), ex = toWorld.vector({1, 0, 0}), ey = toWorld.vector({0, 1, 0});
    const Vec3 r{std::hypot(ex.x, ey.x), std::hypot(ex.y, ey.y), std::hypot(ex.z, ey.z)};
    s.bounds_ = {};
    s.bounds_.expand(c - r);
    s.bounds_.expand(c + r);
    return s;
}

RayEndpoint Shape::trianglePoint(uint32_t prim, const Vec3& p0, const Vec3& p1, const Vec3& p2, double b0, double b1,
                                 double b2) const {
    RayEndpoint e;
    e.p = p0 * b0 + p1 * b1 + p2 * b2;
    e.magnitude = maxComponent(max(abs(p0), max(abs(p1), abs(p2))));
    e.ng = geometricNormals_[prim]; // flipNormals applied already
    // Coordinates may lie outside the triangle: the manifold walks re-solve a hit's barycentrics in double
    // without the inside test (manifold/manifold_walk.cpp), so on a small triangle they can be off by far
    // more than float ulps. There the side is decided at the point, as for triangles whose side varies.
    const bool inside = b0 >= -InsideMargin && b1 >= -InsideMargin && b2 >= -InsideMargin;
    if (!sideVaries_.empty() && (sideVaries_[prim] || !inside)) {
        // The rule at the point (finishTriangles), then flipNormals.
        const auto& tri = mesh_.triangles[prim];
        const Vec3 N =
            toD(mesh_.normals[tri[0]]) * b0 + toD(mesh_.normals[tri[1]]) * b1 + toD(mesh_.normals[tri[2]]) * b2;
        e.ng = windingNormal(p0, p1, p2);
        if (lengthSquared(N) > 1e-20 && dot(e.ng, N) < 0) e.ng = -e.ng;
        if (flip_) e.ng = -e.ng;
    }
    return e;
}

RayEndpoint Shape::pointAt(uint32_t prim, const Vec2& coords) const {
    RayEndpoint e;
    switch (kind_) {
    case Kind::Triangles: {
        const auto& tri = mesh_.triangles[prim];
        const double b1 = coords.x, b2 = coords.y;
        return trianglePoint(prim, toD(mesh_.positions[tri[0]]), toD(mesh_.positions[tri[1]]),
                             toD(mesh_.positions[tri[2]]), 1 - b1 - b2, b1, b2);
    }
    case Kind::Sphere: {
        const double phi = coords.x * TwoPi, theta = coords.y * Pi;
        const double st = std::sin(theta);
        e.ng = Vec3(st * std::cos(phi), st * std::sin(phi), std::cos(theta));
        e.p = center_ + e.ng * radius_;
        e.magnitude = maxComponent(abs(center_)) + radius_;
        break;
    }
    case Kind::Disk: {
        const double r = coords.x, phi = coords.y * TwoPi;
        e.p = toWorld_.point({r * std::cos(phi), r * std::sin(phi), 0});
        e.ng = normalize(toWorld_.normal({0, 0, 1}));
        e.magnitude = maxComponent(max(abs(bounds_.lo), abs(bounds_.hi)));
        break;
    }
    }
    if (flip_) e.ng = -e.ng;
    return e;
}

SurfaceInteraction Shape::surfaceAt(uint32_t prim, const Vec2& coords) const {
    SurfaceInteraction si;
    si.prim = prim;
    si.coords = coords;
    switch (kind_) {
    case Kind::Triangles: {
        const auto& tri = mesh_.triangles[prim];
        const Vec3 p0 = toD(mesh_.positions[tri[0]]), p1 = toD(mesh_.positions[tri[1]]),
                   p2 = toD(mesh_.positions[tri[2]]);
        const double b1 = coords.x, b2 = coords.y, b0 = 1 - b1 - b2;
        const RayEndpoint e = trianglePoint(prim, p0, p1, p2, b0, b1, b2);
        si.p = e.p;
        si.ng = e.ng;
        si.magnitude = e.magnitude;
        // Parameterization: the mesh's uvs, or pbrt's default (0,0), (1,0), (1,1).
        Vec2 uv0{0, 0}, uv1{1, 0}, uv2{1, 1};
        if (!mesh_.uvs.empty()) {
            uv0 = Vec2(mesh_.uvs[tri[0]]);
            uv1 = Vec2(mesh_.uvs[tri[1]]);
            uv2 = Vec2(mesh_.uvs[tri[2]]);
        }
        // Kept as stored even where it is degenerate: textures read si.uv, not the chart below.
        si.uv = uv0 * b0 + uv1 * b1 + uv2 * b2;
        // The chart of dp/du, dp/dv, dn/du, dn/dv: the uvs, unless they do not span the triangle
        // (meshes with every uv at 0, as veach-bidir's egg). Then, as pbrt-v3, an orthonormal frame
        // (s, t) of the triangle's plane built from ng: its chart coordinates are the vertex positions
        // in that frame (relative to p2, for precision far from the origin), so dp/du = s, dp/dv = t and
        // the normal's derivatives come from the same formula as with uvs. The manifold walks need them
        // (the curvature part of the constraint Jacobian).
        TriangleChart chart(uv0, uv1, uv2);
        bool uvChart = std::abs(chart.det) >= 1e-12;
        if (uvChart) {
            std::tie(si.dpdu, si.dpdv) = chart.derivatives(p0, p1, p2);
            uvChart = lengthSquared(cross(si.dpdu, si.dpdv)) > 0;
        }
        if (!uvChart) {
            const Frame f = Frame::fromNormal(si.ng);
            const auto inPlane = [&](const Vec3& p) { return Vec2(dot(p - p2, f.s), dot(p - p2, f.t)); };
            chart = TriangleChart(inPlane(p0), inPlane(p1), Vec2());
            si.dpdu = f.s;
            si.dpdv = f.t;
        }
        Vec3 ns = si.ng;
        if (!mesh_.normals.empty()) {
            const Vec3 n0 = toD(mesh_.normals[tri[0]]), n1 = toD(mesh_.normals[tri[1]]), n2 = toD(mesh_.normals[tri[2]]);
            const Vec3 N = n0 * b0 + n1 * b1 + n2 * b2;
            if (lengthSquared(N) > 1e-20) {
                // trianglePoint already turned ng to the side of N (and flipped it with flipNormals).
                const double sign = flip_ ? -1.0 : 1.0;
                ns = normalize(N) * sign;
                // chart.det is zero only on a triangle without area.
                if (normalsVary_[prim] && chart.det != 0) {
                    const auto [dNdu, dNdv] = chart.derivatives(n0, n1, n2);
                    // The normal field is the NORMALIZED interpolated normal: differentiate that.
                    const double invLength = 1 / length(N);
                    si.dndu = normalizedDerivative(N * invLength, invLength, dNdu) * sign;
                    si.dndv = normalizedDerivative(N * invLength, invLength, dNdv) * sign;
                }
            }
        }
        si.shading = Frame::fromNormalTangent(ns, si.dpdu);
        break;
    }
    case Kind::Sphere: {
        // uv = (phi / 2pi, theta / pi) about the world axes.
        const double phi = coords.x * TwoPi, theta = coords.y * Pi;
        const double st = std::sin(theta), ct = std::cos(theta), sp = std::sin(phi), cp = std::cos(phi);
        const Vec3 n{st * cp, st * sp, ct};
        si.p = center_ + n * radius_;
        si.magnitude = maxComponent(abs(center_)) + radius_;
        si.uv = coords;
        si.dpdu = Vec3(-st * sp, st * cp, 0) * (TwoPi * radius_);
        si.dpdv = Vec3(ct * cp, ct * sp, -st) * (Pi * radius_);
        // n = (p - c) / r, so dn = dp / r exactly: the curvature the manifold walks need.
        const double sign = flip_ ? -1.0 : 1.0;
        si.dndu = si.dpdu * (sign / radius_);
        si.dndv = si.dpdv * (sign / radius_);
        si.ng = n * sign;
        si.shading = Frame::fromNormalTangent(si.ng, si.dpdu);
        break;
    }
    case Kind::Disk: {
        // uv = (r, phi / 2pi) as in Mitsuba's disk.
        const double r = coords.x, phi = coords.y * TwoPi;
        const double sp = std::sin(phi), cp = std::cos(phi);
        si.p = toWorld_.point({r * cp, r * sp, 0});
        si.magnitude = maxComponent(max(abs(bounds_.lo), abs(bounds_.hi)));
        si.uv = coords;
        si.dpdu = toWorld_.vector({cp, sp, 0});
        si.dpdv = toWorld_.vector({-sp, cp, 0}) * (TwoPi * r);
        Vec3 n = normalize(toWorld_.normal({0, 0, 1}));
        if (flip_) n = -n;
        si.ng = n;
        si.shading = Frame::fromNormalTangent(n, si.dpdu);
        break;
    }
    }
    if (bump) applyBumpMap(si, *bump);
    return si;
}

Vec2 Shape::analyticCoords(const Vec3& p) const {
    if (kind_ == Kind::Sphere) {
        const Vec3 d = (p - center_) / radius_;
        double phi = std::atan2(d.y, d.x);
        if (phi < 0) phi += TwoPi;
        return {phi * InvTwoPi, safeAcos(d.z / length(d)) * InvPi};
    }
    const Vec3 l = toWorld_.inverse().point(p);
    double phi = std::atan2(l.y, l.x);
    if (phi < 0) phi += TwoPi;
    return {std::hypot(l.x, l.y), phi * InvTwoPi};
}

PositionSample Shape::samplePosition(const Vec2& u) const {
    PositionSample ps;
    ps.pdfArea = 1.0 / area_;
    switch (kind_) {
    case Kind::Triangles: {
        double ux = u.x;
        ps.prim = uint32_t(triangleAreas_.sampleReuse(ux));
        ps.coords = warp::squareToUniformTriangle({ux, u.y});
        break;
    }
    case Kind::Sphere: {
        const Vec3 d = warp::squareToUniformSphere(u);
        double phi = std::atan2(d.y, d.x);
        if (phi < 0) phi += TwoPi;
        ps.coords = {phi * InvTwoPi, safeAcos(d.z) * InvPi};
        break;
    }
    case Kind::Disk: {
        const Vec2 d = warp::squareToUniformDiskConcentric(u);
        double phi = std::atan2(d.y, d.x);
        if (phi < 0) phi += TwoPi;
        ps.coords = {length(d), phi * InvTwoPi};
        break;
    }
    }
    const RayEndpoint e = pointAt(ps.prim, ps.coords);
    ps.p = e.p;
    ps.n = e.ng;
    ps.magnitude = e.magnitude;
    return ps;
}

double Shape::intersectAnalytic(const Vec3& o, const Vec3& d, double tmin, double tmax) const {
    if (kind_ == Kind::Sphere) {
        // pbrt-v4's robust discriminant: 4a (r^2 - |f - (f.d / d.d) d|^2) avoids the cancellation of
        // b^2 - 4ac for small spheres far from the ray origin.
        const Vec3 f = o - center_;
        const double a = dot(d, d), b = 2 * dot(f, d), c = dot(f, f) - radius_ * radius_;
        const Vec3 v = f - d * (dot(f, d) / a);
        const double disc = 4 * a * (radius_ * radius_ - dot(v, v));
        if (disc < 0) return -1;
        const double root = std::sqrt(disc);
        const double q = b < 0 ? -0.5 * (b - root) : -0.5 * (b + root);
        double t0 = q / a, t1 = q != 0 ? c / q : t0;
        if (t0 > t1) std::swap(t0, t1);
        if (t0 > tmin && t0 < tmax) return t0;
        if (t1 > tmin && t1 < tmax) return t1;
        return -1;
    }
    const Transform inv = toWorld_.inverse();
    const Vec3 ol = inv.point(o), dl = inv.vector(d);
    if (dl.z == 0) return -1;
    const double t = -ol.z / dl.z;
    if (!(t > tmin && t < tmax)) return -1;
    const double x = ol.x + t * dl.x, y = ol.y + t * dl.y;
    return x * x + y * y <= 1.0 ? t : -1;
}

TriangleMesh makeRectangleMesh() {
    TriangleMesh m;
    m.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
    m.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    m.triangles = {{0, 1, 2}, {2, 3, 0}};
    return m;
}

TriangleMesh makeCubeMesh() {
    TriangleMesh m;
    // Each face: outward normal n, two in-plane axes (a, b) with a x b = n so the winding faces out.
    const Vec3f faces[6][3] = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}},   {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
                               {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}},   {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
                               {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},   {{0, 0, -1}, {0, 1, 0}, {1, 0, 0}}};
    for (const auto& f : faces) {
        const Vec3f n = f[0], a = f[1], b = f[2];
        const auto base = uint32_t(m.positions.size());
        const float su[4] = {-1, 1, 1, -1}, sv[4] = {-1, -1, 1, 1};
        for (int k = 0; k < 4; ++k) {
            m.positions.push_back(n + a * su[k] + b * sv[k]);
            m.normals.push_back(n);
            m.uvs.push_back({(su[k] + 1) * 0.5f, (sv[k] + 1) * 0.5f});
        }
        m.triangles.push_back({base, base + 1, base + 2});
        m.triangles.push_back({base + 2, base + 3, base});
    }
    return m;
}

void transformMesh(TriangleMesh& mesh, const Transform& toWorld) {
    for (auto& p : mesh.positions) p = Vec3f(toWorld.point(Vec3(p)));
    for (auto& n : mesh.normals) {
        const Vec3 t = toWorld.normal(Vec3(n));
        const double len = length(t);
        n = len > 0 ? Vec3f(t / len) : n;
    }
}

} // namespace lt
