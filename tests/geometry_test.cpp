// Intersection and differential geometry against analytic spheres and planes; ray offsets at extreme
// scene scales.
#include <catch2/catch.hpp>

#include <cmath>

#include "math/constants.h"
#include "math/rng.h"
#include "math/warp.h"
#include "scene/scene.h"

using namespace lt;

namespace {

Vec2 rand2(Pcg32& rng) { return {rng.nextDouble(), rng.nextDouble()}; }

// Central differences of a surface's position and shading normal along its uv parameterization,
// compared with the analytic dp/du, dp/dv, dn/du, dn/dv. The step h gives an O(h^2) truncation error;
// the tolerance allows 1e3 times h^2 times the scale of the second derivatives (curvature ~ 1 here).
void checkDerivatives(const Shape& shape, uint32_t prim, const std::function<Vec2(const Vec2&)>& uvToCoords,
                      const Vec2& uv, double scale) {
    const double h = 1e-5;
    const SurfaceInteraction si = shape.surfaceAt(prim, uvToCoords(uv));
    const SurfaceInteraction up = shape.surfaceAt(prim, uvToCoords({uv.x + h, uv.y}));
    const SurfaceInteraction um = shape.surfaceAt(prim, uvToCoords({uv.x - h, uv.y}));
    const SurfaceInteraction vp = shape.surfaceAt(prim, uvToCoords({uv.x, uv.y + h}));
    const SurfaceInteraction vm = shape.surfaceAt(prim, uvToCoords({uv.x, uv.y - h}));
    const double tol = 1e-5 * scale;
    const Vec3 dpdu = (up.p - um.p) / (2 * h), dpdv = (vp.p - vm.p) / (2 * h);
    const Vec3 dndu = (up.shading.n - um.shading.n) / (2 * h), dndv = (vp.shading.n - vm.shading.n) / (2 * h);
    CHECK(length(dpdu - si.dpdu) < tol);
    CHECK(length(dpdv - si.dpdv) < tol);
    CHECK(length(dndu - si.dndu) < tol / scale * 10);
    CHECK(length(dndv - si.dndv) < tol / scale * 10);
    // The shading frame is orthonormal with n the shading normal.
    CHECK(std::abs(dot(si.shading.s, si.shading.n)) < 1e-12);
    CHECK(std::abs(length(si.shading.t) - 1) < 1e-12);
}

Scene sceneOf(std::vector<Shape> shapes) {
    Scene s;
    s.shapes = std::move(shapes);
    s.finalize();
    return s;
}

} // namespace

TEST_CASE("sphere intersection is exact in double precision", "[geometry]") {
    const Vec3 c{1.5, -2, 0.25};
    const double r = 0.75;
    const Scene scene = sceneOf({Shape::sphere(c, r, false)});
    Pcg32 rng(7, 1);
    for (int i = 0; i < 1000; ++i) {
        const Vec3 target = c + warp::squareToUniformSphere(rand2(rng)) * (r * 0.99);
        Ray ray;
        ray.o = c + warp::squareToUniformSphere(rand2(rng)) * (5 * r);
        ray.d = normalize(target - ray.o);
        const auto si = scene.intersect(ray);
        REQUIRE(si);
        CHECK(std::abs(length(si->p - c) - r) < 1e-12 * r);
        CHECK(length(si->ng - (si->p - c) / r) < 1e-9);
        // The analytic entry distance.
        const Vec3 f = ray.o - c;
        const double b = dot(f, ray.d), disc = b * b - (dot(f, f) - r * r);
        CHECK(si->t == Approx(-b - std::sqrt(disc)).epsilon(1e-9));
    }
}

TEST_CASE("plane intersection and the rectangle's frame", "[geometry]") {
    TriangleMesh m = makeRectangleMesh();
    transformMesh(m, Transform::translate({0, 0, 2}) * Transform::scale({3, 1, 1}));
    const Scene scene = sceneOf({Shape::triangles(m, false)});
    Pcg32 rng(3, 2);
    for (int i = 0; i < 200; ++i) {
        const Vec2 q{rng.nextDouble() * 5.8 - 2.9, rng.nextDouble() * 1.9 - 0.95};
        Ray ray;
        ray.o = {q.x * 0.5, q.y * 0.5, -1};
        ray.d = normalize(Vec3(q.x, q.y, 2) - ray.o);
        const auto si = scene.intersect(ray);
        REQUIRE(si);
        CHECK(si->p.z == Approx(2.0).margin(1e-6));
        CHECK(si->p.x == Approx(q.x).margin(1e-5));
        CHECK(si->t == Approx(length(Vec3(q.x, q.y, 2) - ray.o)).epsilon(1e-6));
        CHECK(si->ng.z == Approx(1.0));
        // dp/du of Mitsuba's rectangle: uv spans [0,1] over the 2-unit side scaled by 3.
        CHECK(si->dpdu.x == Approx(6.0));
        CHECK(si->dpdv.y == Approx(2.0));
    }
}

TEST_CASE("differential geometry matches finite differences", "[geometry]") {
    SECTION("sphere (uv = phi/2pi, theta/pi)") {
        for (bool flip : {false, true}) {
            const Shape s = Shape::sphere({0.3, -0.2, 1}, 2.0, flip);
            Pcg32 rng(11, flip);
            for (int i = 0; i < 50; ++i) {
                const Vec2 uv{0.05 + 0.9 * rng.nextDouble(), 0.05 + 0.9 * rng.nextDouble()};
                checkDerivatives(s, 0, [](const Vec2& x) { return x; }, uv, 2.0 * Pi);
            }
        }
    }
    SECTION("triangle with interpolated normals and uvs") {
        TriangleMesh m;
        m.positions = {{0, 0, 0}, {1, 0.1f, 0}, {0.2f, 1, 0.3f}};
        m.normals = {Vec3f(normalize(Vec3(0.1, 0, 1))), Vec3f(normalize(Vec3(0.4, -0.2, 1))),
                     Vec3f(normalize(Vec3(-0.3, 0.5, 1)))};
        m.uvs = {{0.1f, 0.2f}, {0.9f, 0.1f}, {0.3f, 0.8f}};
        m.triangles = {{0, 1, 2}};
        for (bool flip : {false, true}) {
            const Shape s = Shape::triangles(m, flip);
            // uv -> barycentrics of this triangle.
            const Vec2 uv0 = Vec2(m.uvs[0]), e1 = Vec2(m.uvs[1]) - uv0, e2 = Vec2(m.uvs[2]) - uv0;
            const double det = e1.x * e2.y - e1.y * e2.x;
            auto coords = [=](const Vec2& uv) {
                const Vec2 d = uv - uv0;
                return Vec2((d.x * e2.y - d.y * e2.x) / det, (e1.x * d.y - e1.y * d.x) / det);
            };
            Pcg32 rng(5, flip);
            for (int i = 0; i < 50; ++i) {
                const Vec2 b = warp::squareToUniformTriangle(rand2(rng));
                const Vec2 uv = uv0 + e1 * b.x + e2 * b.y;
                checkDerivatives(s, 0, coords, uv, 2.0);
                // The shading normal is the normalized interpolated normal, flipped with flipNormals.
                const SurfaceInteraction si = s.surfaceAt(0, b);
                const Vec3 N = Vec3(m.normals[0]) * (1 - b.x - b.y) + Vec3(m.normals[1]) * b.x + Vec3(m.normals[2]) * b.y;
                CHECK(length(si.shading.n - normalize(N) * (flip ? -1.0 : 1.0)) < 1e-6);
                CHECK(dot(si.ng, si.shading.n) > 0);
            }
        }
    }
    SECTION("triangle with interpolated normals and degenerate uvs (all 0): the plane's frame as chart") {
        // veach-bidir's egg has every uv at 0. surfaceAt then charts the triangle's plane with an
        // orthonormal frame (pbrt-v3), and dn/du, dn/dv must be the derivatives of the normalized
        // shading normal along that same chart (the manifold walks' curvature terms).
        TriangleMesh m;
        m.positions = {{0, 0, 0}, {1, 0.1f, 0}, {0.2f, 1, 0.3f}};
        m.normals = {Vec3f(normalize(Vec3(0.1, 0, 1))), Vec3f(normalize(Vec3(0.4, -0.2, 1))),
                     Vec3f(normalize(Vec3(-0.3, 0.5, 1)))};
        m.uvs.assign(3, Vec2f(0, 0));
        m.triangles = {{0, 1, 2}};
        const Vec3 p0(m.positions[0]), e1 = Vec3(m.positions[1]) - p0, e2 = Vec3(m.positions[2]) - p0;
        for (bool flip : {false, true}) {
            const Shape s = Shape::triangles(m, flip);
            const SurfaceInteraction c = s.surfaceAt(0, {1.0 / 3, 1.0 / 3});
            // The chart spans the triangle's plane (orthonormal, normal to ng) and is the same everywhere.
            CHECK(std::abs(length(c.dpdu) - 1) < 1e-12);
            CHECK(std::abs(length(c.dpdv) - 1) < 1e-12);
            CHECK(std::abs(dot(c.dpdu, c.dpdv)) < 1e-12);
            CHECK(length(cross(c.dpdu, c.dpdv) - c.ng) < 1e-12);
            // Chart coordinates (u, v) -> the point p0 + u dp/du + v dp/dv -> its barycentrics.
            const double g11 = dot(e1, e1), g12 = dot(e1, e2), g22 = dot(e2, e2), det = g11 * g22 - g12 * g12;
            auto coords = [=](const Vec2& uv) {
                const Vec3 d = c.dpdu * uv.x + c.dpdv * uv.y;
                const double r1 = dot(e1, d), r2 = dot(e2, d);
                return Vec2((g22 * r1 - g12 * r2) / det, (g11 * r2 - g12 * r1) / det);
            };
            Pcg32 rng(7, flip);
            for (int i = 0; i < 50; ++i) {
                const Vec2 b = warp::squareToUniformTriangle(rand2(rng));
                const Vec3 d = e1 * b.x + e2 * b.y;
                checkDerivatives(s, 0, coords, {dot(d, c.dpdu), dot(d, c.dpdv)}, 1.0);
                const SurfaceInteraction si = s.surfaceAt(0, b);
                CHECK(length(si.dpdu - c.dpdu) < 1e-12);
                CHECK(length(si.dpdv - c.dpdv) < 1e-12);
                // The normals vary over the face: a flat answer would not be the normal field's.
                CHECK(lengthSquared(si.dndu) + lengthSquared(si.dndv) > 0.01);
                // Textures read the uvs as stored, not the chart.
                CHECK(si.uv == Vec2(0, 0));
            }
        }
    }
    SECTION("triangle with interpolated normals and no uvs: pbrt's default uvs (0,0), (1,0), (1,1)") {
        TriangleMesh m;
        m.positions = {{0, 0, 0}, {1, 0.1f, 0}, {0.2f, 1, 0.3f}};
        m.normals = {Vec3f(normalize(Vec3(0.1, 0, 1))), Vec3f(normalize(Vec3(0.4, -0.2, 1))),
                     Vec3f(normalize(Vec3(-0.3, 0.5, 1)))};
        m.triangles = {{0, 1, 2}};
        const Shape s = Shape::triangles(m, false);
        // uv = b1 (1,0) + b2 (1,1), so b1 = u - v, b2 = v.
        auto coords = [](const Vec2& uv) { return Vec2(uv.x - uv.y, uv.y); };
        Pcg32 rng(9, 0);
        for (int i = 0; i < 50; ++i) {
            const Vec2 b = warp::squareToUniformTriangle(rand2(rng));
            checkDerivatives(s, 0, coords, {b.x + b.y, b.y}, 2.0);
        }
    }
    SECTION("disk (uv = r, phi/2pi)") {
        const Shape s = Shape::disk(Transform::translate({0, 1, 0}) * Transform::rotate({1, 0, 0}, 30) *
                                        Transform::scale({2, 2, 2}),
                                    false);
        Pcg32 rng(13, 0);
        for (int i = 0; i < 50; ++i) {
            const Vec2 uv{0.1 + 0.8 * rng.nextDouble(), rng.nextDouble()};
            checkDerivatives(s, 0, [](const Vec2& x) { return x; }, uv, 4.0 * Pi);
        }
    }
}

TEST_CASE("a triangle's geometric normal takes its shading normals' side, per triangle or per point", "[geometry]") {
    // pbrt-v3's rule, point by point: the winding's normal, turned to the side of the interpolated shading
    // normal (when there is one), then flipped with flipNormals. Shape decides it once per triangle where
    // all three vertex normals share a side; this checks both paths against the rule, inside the triangles
    // and outside them (the manifold walks' re-solved barycentrics may leave a triangle).
    const Vec3f up(0, 0, 1), tilted = Vec3f(normalize(Vec3(0.3, 0, 1))), down(0, 0, -1);
    const Vec3f grazing = Vec3f(normalize(Vec3(1, 0, 0.002))); // on the side of up, barely
    TriangleMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    // Vertices 0-2: every normal on the side of the winding of triangle 0. Vertices 3-5: on both sides, so
    // the side varies over the face. Vertices 6-8: on one side, but the third barely, so that just outside
    // the triangle the interpolated normal crosses to the other side. Then the same with reversed winding.
    m.normals = {up, up, tilted, up, tilted, down, up, up, grazing};
    m.triangles = {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}, {0, 2, 1}, {3, 5, 4}, {6, 8, 7}};
    const auto rule = [&](uint32_t prim, const Vec2& b, bool flip) {
        const auto& t = m.triangles[prim];
        const Vec3 p0(m.positions[t[0]]), p1(m.positions[t[1]]), p2(m.positions[t[2]]);
        Vec3 ng = normalize(cross(p1 - p0, p2 - p0));
        const Vec3 N =
            Vec3(m.normals[t[0]]) * (1 - b.x - b.y) + Vec3(m.normals[t[1]]) * b.x + Vec3(m.normals[t[2]]) * b.y;
        if (lengthSquared(N) > 1e-20 && dot(ng, N) < 0) ng = -ng;
        return flip ? -ng : ng;
    };
    for (bool flip : {false, true}) {
        const Shape s = Shape::triangles(m, flip);
        Pcg32 rng(17, flip);
        int flipsWithinTriangle = 0;
        for (uint32_t prim = 0; prim < m.triangles.size(); ++prim) {
            bool seen[2] = {false, false};
            for (int i = 0; i < 200; ++i) {
                const Vec2 b = warp::squareToUniformTriangle(rand2(rng));
                const Vec3 expected = rule(prim, b, flip);
                CHECK(s.pointAt(prim, b).ng == expected);
                CHECK(s.surfaceAt(prim, b).ng == expected);
                seen[expected.z > 0] = true;
                // Around the triangle, up to 0.1 outside it.
                const Vec2 around{rng.nextDouble() * 1.2 - 0.1, rng.nextDouble() * 1.2 - 0.1};
                CHECK(s.pointAt(prim, around).ng == rule(prim, around, flip));
            }
            flipsWithinTriangle += seen[0] && seen[1];
        }
        // Triangles 1 and 4 (one per winding) are the ones whose side varies inside the face.
        CHECK(flipsWithinTriangle == 2);
        // Just outside triangle 2 near its grazing vertex, the rule turns the normal: (b0, b1, b2) =
        // (-0.01, -0.01, 1.02) gives the interpolated normal a component of -0.02 + 1.02 x 0.002 = -0.018
        // along the winding's normal.
        const Vec2 outside{-0.01, 1.02};
        CHECK(rule(2, outside, flip).z * rule(2, {0.2, 0.2}, flip).z < 0);
        CHECK(s.pointAt(2, outside).ng == rule(2, outside, flip));
        CHECK(s.pointAt(5, {1.02, -0.01}).ng == rule(5, {1.02, -0.01}, flip));
    }
}

TEST_CASE("dn/du and dn/dv are zero exactly where the three vertex normals are one", "[geometry]") {
    TriangleMesh m;
    m.positions = {{0, 0, 0}, {1, 0.1f, 0}, {0.2f, 1, 0.3f}};
    m.uvs = {{0.1f, 0.2f}, {0.9f, 0.1f}, {0.3f, 0.8f}};
    m.triangles = {{0, 1, 2}};
    const Vec3f n = Vec3f(normalize(Vec3(0.1, -0.2, 1))), other = Vec3f(normalize(Vec3(-0.3, 0.4, 1)));
    m.normals = {n, n, n};
    const SurfaceInteraction flat = Shape::triangles(m, false).surfaceAt(0, {0.3, 0.2});
    CHECK(flat.dndu == Vec3());
    CHECK(flat.dndv == Vec3());
    // The float normal's length is 1 within its rounding (3 components, 2^-24 each): about 6e-8.
    CHECK(length(flat.shading.n - Vec3(n)) < 1e-7);
    // Any one vertex normal apart from the other two (each pairing) and the normal field turns.
    for (int apart = 0; apart < 3; ++apart) {
        m.normals = {n, n, n};
        m.normals[size_t(apart)] = other;
        const SurfaceInteraction si = Shape::triangles(m, false).surfaceAt(0, {0.3, 0.2});
        CHECK(lengthSquared(si.dndu) + lengthSquared(si.dndv) > 0.01);
    }
}

TEST_CASE("ray offsets avoid self-intersection from scene scale 1e-3 to 1e5", "[geometry]") {
    for (double scale : {1e-3, 1.0, 1e3, 1e5}) {
        CAPTURE(scale);
        // A sphere far from the origin (float ulps there are large compared to the radius' ulps) above
        // a ground plane facing it.
        const Vec3 c = Vec3(40, 25, -30) * scale;
        const double r = scale;
        TriangleMesh ground = makeRectangleMesh();
        transformMesh(ground, Transform::translate(c - Vec3(0, 2 * r, 0)) * Transform::rotate({1, 0, 0}, -90) *
                                  Transform::scale({10 * r, 10 * r, 1}));
        const Scene scene = sceneOf({Shape::sphere(c, r, false), Shape::triangles(ground, false)});
        Pcg32 rng(17, uint64_t(std::log10(scale) + 10));
        int selfHits = 0, missedExits = 0, falseShadows = 0;
        const int n = 2000;
        for (int i = 0; i < n; ++i) {
            // A point on the sphere, reached by a ray from outside as a renderer would.
            Ray cam;
            cam.o = c + Vec3(0, 0, 8 * r) + Vec3(rng.nextDouble() - 0.5, rng.nextDouble() - 0.5, 0) * r;
            cam.d = normalize(c + warp::squareToUniformSphere(rand2(rng)) * (0.9 * r) - cam.o);
            const auto hit = scene.intersect(cam);
            if (!hit || hit->shape != 0) continue;
            const Frame frame = Frame::fromNormal(hit->ng);
            // Leaving outward: must not hit the sphere again (it is convex).
            const Vec3 out = frame.toWorld(warp::squareToCosineHemisphere(rand2(rng)));
            const auto again = scene.intersect(spawnRay(hit->endpoint(), out));
            if (again && again->shape == 0) ++selfHits;
            // Entering (refraction): must reach the far side, not stop at the entry point. Moving the
            // origin by e changes the exit distance by at most |e| (1 + 1/cos) to first order (the chord
            // leaves at the angle it entered), so twice that bounds the error.
            const Vec3 in = -out;
            const double cosIn = dot(out, hit->ng);
            const Vec3 o = offsetRayOrigin(hit->endpoint(), in);
            const auto inside = scene.intersect(spawnRay(hit->endpoint(), in));
            const double chord = 2 * r * cosIn;
            const double tol = 2 * length(o - hit->p) * (1 + 1 / cosIn) + 1e-12 * r;
            if (!inside || inside->shape != 0 || std::abs(length(inside->p - hit->p) - chord) > tol) ++missedExits;
            // A shadow ray to the ground point right below a downward-facing sphere point is free.
            if (hit->ng.y < -0.5) {
                const Vec3 g = hit->p - Vec3(0, (hit->p.y - (c.y - 2 * r)), 0);
                const RayEndpoint ground{g, {0, 1, 0}, maxComponent(abs(c)) + 10 * r};
                if (scene.occluded(spawnRayTo(hit->endpoint(), ground))) ++falseShadows;
            }
        }
        CHECK(selfHits == 0);
        CHECK(missedExits == 0);
        CHECK(falseShadows == 0);
        // The ground plane: rays leaving it upward never hit it again.
        int planeSelf = 0;
        for (int i = 0; i < n; ++i) {
            Ray down;
            down.o = c + Vec3((rng.nextDouble() - 0.5) * 16 * r, 0, (rng.nextDouble() - 0.5) * 16 * r) + Vec3(0, 1.5 * r, 0);
            down.o.x += 3 * r;   // beside the sphere
            down.d = normalize(Vec3(rng.nextDouble() - 0.5, -1, rng.nextDouble() - 0.5));
            const auto hit = scene.intersect(down);
            if (!hit || hit->shape != 1) continue;
            const Vec3 up = Frame::fromNormal(hit->ng).toWorld(warp::squareToCosineHemisphere(rand2(rng)));
            const auto again = scene.intersect(spawnRay(hit->endpoint(), up));
            if (again && again->shape == 1) ++planeSelf;
        }
        CHECK(planeSelf == 0);
    }
}
