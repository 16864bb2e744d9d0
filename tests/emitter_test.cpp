// Emitters: every sampling routine against its own density function, densities that integrate to one,
// and estimators against closed forms (irradiance of sphere, rectangle and disk lights; total power).
// Tolerances are 5 standard errors of the estimator at hand (fixed seeds, so a failure is reproducible);
// exact identities are checked to round-off.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <unistd.h>
#include <vector>

#include "math/constants.h"
#include "util/error.h"
#include "math/rng.h"
#include "math/warp.h"
#include "path/vertex.h"
#include "scene/emitter.h"
#include "scene/emitters/hosek_wilkie_sky.h"
#include "scene/emitters/preetham_sun.h"
#include "scene/emitters/sun_position.h"
#include "scene/emitters/sun_sky.h"
#include "scene/scene.h"
#include "test_util.h"

using namespace lt;

namespace {

struct Stats {
    double n = 0, sum = 0, sum2 = 0;
    void add(double x) {
        n += 1;
        sum += x;
        sum2 += x * x;
    }
    [[nodiscard]] double mean() const { return sum / n; }
    [[nodiscard]] double stdErr() const { return std::sqrt(std::max(0.0, sum2 / n - sqr(mean())) / n); }
};

// |estimate - expected| within 5 standard errors, plus a round-off floor for zero-variance estimators.
void checkWithin(const Stats& s, double expected) {
    INFO("estimate " << s.mean() << " +- " << s.stdErr() << ", expected " << expected);
    CHECK(std::abs(s.mean() - expected) <= 5 * s.stdErr() + 1e-9 * std::abs(expected));
}

Vec2 next2(Pcg32& rng) {
    const double a = rng.nextDouble();
    return {a, rng.nextDouble()};
}

// A rectangle light: Mitsuba's [-1,1]^2 rectangle (normal +z) scaled to half-sizes (a, b), turned to face
// -z and raised to height h. Seen from the origin with normal +z it faces the point.
Shape rectangleFacingDown(double a, double b, double h) {
    TriangleMesh m = makeRectangleMesh();
    transformMesh(m, Transform::translate({0, 0, h}) * Transform::rotate({1, 0, 0}, 180) *
                         Transform::scale({a, b, 1}));
    return Shape::triangles(m, false);
}

Shape diskFacingDown(double radius, double h) {
    return Shape::disk(Transform::translate({0, 0, h}) * Transform::rotate({1, 0, 0}, 180) *
                           Transform::scale({radius, radius, 1}),
                       false);
}

// The first point of the shape along a ray (analytic shapes exactly, triangles by Moller-Trumbore in
// double), with its geometric normal; what a renderer's ray cast would report.
struct Hit {
    Vec3 p, n;
};
std::optional<Hit> trace(const Shape& shape, const Vec3& o, const Vec3& d) {
    if (shape.kind() != Shape::Kind::Triangles) {
        const double t = shape.intersectAnalytic(o, d, 0, 1e300);
        if (t < 0) return std::nullopt;
        const Vec3 p = o + d * t;
        return Hit{p, shape.surfaceAt(0, shape.analyticCoords(p)).ng};
    }
    const TriangleMesh& m = shape.mesh();
    double best = 1e300;
    std::optional<Hit> hit;
    for (uint32_t i = 0; i < m.triangles.size(); ++i) {
        const auto& tri = m.triangles[i];
        const Vec3 p0(m.positions[tri[0]]), p1(m.positions[tri[1]]), p2(m.positions[tri[2]]);
        const Vec3 e1 = p1 - p0, e2 = p2 - p0, q = cross(d, e2);
        const double det = dot(e1, q);
        if (det == 0) continue;
        const Vec3 s = o - p0;
        const double b1 = dot(s, q) / det;
        const Vec3 r = cross(s, e1);
        const double b2 = dot(d, r) / det, t = dot(e2, r) / det;
        if (b1 < 0 || b2 < 0 || b1 + b2 > 1 || t <= 0 || t >= best) continue;
        best = t;
        hit = Hit{o + d * t, shape.surfaceAt(i, {b1, b2}).ng};
    }
    return hit;
}

// Form factor from a differential area to a parallel rectangle a x b at distance h, the area element
// below one corner (Howell's catalog, configuration B-3).
double cornerFormFactor(double a, double b, double h) {
    const double x = a / h, y = b / h, sx = std::sqrt(1 + x * x), sy = std::sqrt(1 + y * y);
    return (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy)) / TwoPi;
}

// For every direct sample: pdfDirect reproduces its density, and wi, dist and p agree.
void checkDirectConsistency(const Emitter& e, const Vec3& ref, int n, uint64_t seed) {
    Pcg32 rng(seed, 1);
    int valid = 0;
    for (int i = 0; i < n; ++i) {
        const DirectSample ds = e.sampleDirect(ref, next2(rng));
        if (!(ds.pdf > 0)) continue;
        ++valid;
        const double pdf = e.pdfDirect(ref, ds.p, ds.n, ds.wi);
        INFO(e.typeName() << " sample " << i);
        REQUIRE(pdf == Approx(ds.pdf).epsilon(1e-9));
        CHECK(length(ds.wi) == Approx(1).epsilon(1e-12));
        if (std::isfinite(ds.dist)) CHECK(length(ref + ds.wi * ds.dist - ds.p) <= 1e-9 * (1 + ds.dist));
    }
    CHECK(valid > n / 2);
}

// Monte Carlo integral of the direct-sampling density over the sphere of directions, with directions
// uniform on the sphere traced to the emitter; must be 1.
Stats directDensityIntegral(const Emitter& e, const Shape* shape, const Vec3& ref, int n, uint64_t seed) {
    Pcg32 rng(seed, 2);
    Stats s;
    for (int i = 0; i < n; ++i) {
        const Vec3 d = warp::squareToUniformSphere(next2(rng));
        double pdf = 0;
        if (!shape) {
            pdf = e.pdfDirect(ref, Vec3(), -d, d);
        } else if (const auto hit = trace(*shape, ref, d)) {
            pdf = e.pdfDirect(ref, hit->p, hit->n, d);
        }
        s.add(pdf / warp::squareToUniformSpherePdf());
    }
    return s;
}

// Irradiance at ref (normal nRef) by direct sampling: sum of L cos / p.
Stats irradiance(const Emitter& e, const Vec3& ref, const Vec3& nRef, int n, uint64_t seed, int channel = 0) {
    Pcg32 rng(seed, 3);
    Stats s;
    for (int i = 0; i < n; ++i) {
        const DirectSample ds = e.sampleDirect(ref, next2(rng));
        s.add(ds.pdf > 0 ? ds.value[channel] * std::max(0.0, dot(nRef, ds.wi)) / ds.pdf : 0.0);
    }
    return s;
}

// Emission samples: pdfEmission reproduces their densities; returns the power estimate
// value |cos| / (pdfPos pdfDir) (no cosine for point-like emitters, whose n is zero).
Stats emittedPower(const Emitter& e, int n, uint64_t seed, int channel = 0) {
    Pcg32 rng(seed, 4);
    Stats s;
    for (int i = 0; i < n; ++i) {
        const Vec2 u1 = next2(rng), u2 = next2(rng);
        const EmissionSample es = e.sampleEmission(u1, u2);
        if (!(es.pdfPos > 0 && es.pdfDir > 0)) {
            s.add(0);
            continue;
        }
        double pdfPos, pdfDir;
        e.pdfEmission(es.p, es.n, es.d, pdfPos, pdfDir);
        INFO(e.typeName() << " emission sample " << i);
        REQUIRE(pdfPos == Approx(es.pdfPos).epsilon(1e-9));
        REQUIRE(pdfDir == Approx(es.pdfDir).epsilon(1e-9));
        const double cosine = lengthSquared(es.n) > 0 ? std::abs(dot(es.n, es.d)) : 1.0;
        s.add(es.value[channel] * cosine / (es.pdfPos * es.pdfDir));
    }
    return s;
}

} // namespace

TEST_CASE("area emitter: pdfDirect is the density sampleDirect uses", "[emitter]") {
    const Spectrum L(2.0, 1.0, 0.5);
    const Shape sphere = Shape::sphere({0, 0, 0}, 1, false);
    const Shape tiny = Shape::sphere({1, 2, 20}, 0.05, false);
    const Shape rect = rectangleFacingDown(1.5, 0.5, 2);
    const Shape disk = diskFacingDown(0.7, 1.5);
    checkDirectConsistency(*makeAreaEmitter(sphere, 0, L), {3, 1, 0.5}, 4000, 1);     // cone
    checkDirectConsistency(*makeAreaEmitter(sphere, 0, L), {0.2, 0.1, -0.3}, 4000, 2); // inside: area
    checkDirectConsistency(*makeAreaEmitter(tiny, 0, L), {0, 0, 0}, 4000, 3);
    checkDirectConsistency(*makeAreaEmitter(rect, 0, L), {0.3, -0.2, 0}, 4000, 4);
    checkDirectConsistency(*makeAreaEmitter(disk, 0, L), {0.3, -0.2, 0}, 4000, 5);

    SECTION("cone samples lie on the visible cap, far-side points have density 0") {
        const auto e = makeAreaEmitter(sphere, 0, L);
        const Vec3 ref{3, 1, 0.5};
        Pcg32 rng(7, 7);
        for (int i = 0; i < 2000; ++i) {
            const DirectSample ds = e->sampleDirect(ref, next2(rng));
            REQUIRE(length(ds.p) == Approx(1).epsilon(1e-12));
            REQUIRE(dot(ds.p, ref - ds.p) >= -1e-9);   // front of the sphere as seen from ref
        }
        const Vec3 far = -normalize(ref);
        CHECK(e->pdfDirect(ref, far, far, normalize(far - ref)) == 0);
    }
    SECTION("tiny sphere: samples stay on the sphere") {
        const auto e = makeAreaEmitter(tiny, 0, L);
        Pcg32 rng(8, 8);
        for (int i = 0; i < 2000; ++i) {
            const DirectSample ds = e->sampleDirect({0, 0, 0}, next2(rng));
            REQUIRE(length(ds.p - tiny.center()) == Approx(0.05).epsilon(1e-9));
        }
    }
}

TEST_CASE("area emitter: direct-sampling density integrates to one over directions", "[emitter]") {
    const Spectrum L(1.0);
    const Shape sphere = Shape::sphere({0, 0, 0}, 1, false);
    const Shape rect = rectangleFacingDown(1.5, 0.5, 2);
    const Shape disk = diskFacingDown(0.7, 1.5);
    struct Case {
        const Shape* shape;
        Vec3 ref;
        uint64_t seed;
    };
    for (const Case& c : {Case{&sphere, {3, 1, 0.5}, 11}, Case{&sphere, {0.2, 0.1, -0.3}, 12},
                          Case{&rect, {0.3, -0.2, 0}, 13}, Case{&disk, {0.3, -0.2, 0}, 14}}) {
        const auto e = makeAreaEmitter(*c.shape, 0, L);
        checkWithin(directDensityIntegral(*e, c.shape, c.ref, 200000, c.seed), 1.0);
    }
}

TEST_CASE("area emitter: irradiance estimates match closed forms", "[emitter]") {
    const Spectrum L(3.0);
    SECTION("sphere lights: E = pi L sin^2(alpha) cos(theta)") {
        // Veach's MIS scene light (radius 0.05 at distance ~20) and a large, tilted one, both entirely
        // above the receiver's horizon.
        struct Case {
            Vec3 center;
            double radius;
            Vec3 nRef;
        };
        for (const Case& c :
             {Case{{1, 2, 20}, 0.05, {0, 0, 1}}, Case{{0.5, 0, 3}, 1.0, normalize(Vec3(0.3, 0.1, 1))}}) {
            const auto e = makeAreaEmitter(Shape::sphere(c.center, c.radius, false), 0, L);
            const double dc = length(c.center);
            const double expected = Pi * L.r * sqr(c.radius / dc) * dot(c.nRef, c.center / dc);
            checkWithin(irradiance(*e, {0, 0, 0}, c.nRef, 20000, 21), expected);
        }
    }
    SECTION("rectangle light: form factor of a parallel rectangle") {
        // Origin below the center of a 2a x 2b rectangle: four corner configurations.
        const double a = 1.5, b = 0.5, h = 2;
        const auto e = makeAreaEmitter(rectangleFacingDown(a, b, h), 0, L);
        checkWithin(irradiance(*e, {0, 0, 0}, {0, 0, 1}, 200000, 22), Pi * L.r * 4 * cornerFormFactor(a, b, h));
    }
    SECTION("disk light: E = pi L R^2 / (h^2 + R^2) on its axis") {
        const double R = 0.7, h = 1.5;
        const auto e = makeAreaEmitter(diskFacingDown(R, h), 0, L);
        checkWithin(irradiance(*e, {0, 0, 0}, {0, 0, 1}, 200000, 23), Pi * L.r * R * R / (h * h + R * R));
    }
    SECTION("one-sided: nothing arrives behind the emitter") {
        const auto e = makeAreaEmitter(rectangleFacingDown(1, 1, 2), 0, L);
        const Stats s = irradiance(*e, {0, 0, 4}, {0, 0, -1}, 1000, 24);
        CHECK(s.mean() == 0);
    }
}

TEST_CASE("area emitter: emission densities and power", "[emitter]") {
    const Spectrum L(2.0, 1.0, 0.5);
    for (const Shape& shape : {Shape::sphere({0, 1, 0}, 0.5, false), Shape::sphere({0, 1, 0}, 0.5, true),
                               rectangleFacingDown(1.5, 0.5, 2), diskFacingDown(0.7, 1.5)}) {
        const auto e = makeAreaEmitter(shape, 3, L);
        CHECK(e->shape == 3);
        CHECK(e->power().g == Approx(Pi * shape.area() * L.g).epsilon(1e-12));
        checkWithin(emittedPower(*e, 20000, 31, 1), e->power().g);
    }
}

TEST_CASE("point emitter", "[emitter]") {
    const Spectrum I(4.0, 2.0, 1.0);
    const Vec3 pos{1, 2, 3}, ref{-1, 0.5, 0};
    const auto e = makePointEmitter(pos, I);
    CHECK(e->isDelta());
    const DirectSample ds = e->sampleDirect(ref, {0.3, 0.7});
    CHECK(ds.pdf == 1);
    CHECK(e->pdfDirect(ref, ds.p, ds.n, ds.wi) == 1);
    CHECK(length(ds.wi - normalize(pos - ref)) < 1e-15);
    CHECK(ds.value.r == Approx(I.r / lengthSquared(pos - ref)).epsilon(1e-14));
    checkWithin(emittedPower(*e, 2000, 41), e->power().r);
    CHECK(e->power().r == Approx(4 * Pi * I.r).epsilon(1e-14));
}

TEST_CASE("spot emitter: Mitsuba falloff, densities and power", "[emitter]") {
    const Spectrum I(5.0);
    const double cutoff = 30, beam = 20;
    // Placed at (0, 0, 2), shining down -z.
    const Transform toWorld = Transform::translate({0, 0, 2}) * Transform::rotate({1, 0, 0}, 180);
    const auto e = makeSpotEmitter(toWorld, I, cutoff, beam);
    auto valueAtAngle = [&](double deg) {
        const Vec3 ref{std::tan(degToRad(deg)) * 2, 0, 0};
        const DirectSample ds = e->sampleDirect(ref, {0.5, 0.5});
        CHECK(ds.pdf == 1);
        CHECK(e->pdfDirect(ref, ds.p, ds.n, ds.wi) == 1);
        return ds.value.r * lengthSquared(ref - Vec3(0, 0, 2)) / I.r;
    };
    // Mitsuba's falloffCurve: 1 inside beamWidth, (cutoff - theta) / (cutoff - beam) between, 0 beyond.
    CHECK(valueAtAngle(0) == Approx(1));
    CHECK(valueAtAngle(19) == Approx(1));
    CHECK(valueAtAngle(25) == Approx(0.5).epsilon(1e-9));
    CHECK(valueAtAngle(27.5) == Approx(0.25).epsilon(1e-9));
    CHECK(valueAtAngle(31) == 0);
    // Power: closed form 2 pi I [1 - (sin c - sin b)/(c - b)] against the emission estimator.
    const double c = degToRad(cutoff), b = degToRad(beam);
    CHECK(e->power().r == Approx(TwoPi * I.r * (1 - (std::sin(c) - std::sin(b)) / (c - b))).epsilon(1e-12));
    checkWithin(emittedPower(*e, 100000, 51), e->power().r);
    // Degenerate transition (beam = cutoff): a hard-edged cone of solid angle 2 pi (1 - cos c).
    const auto hard = makeSpotEmitter(toWorld, I, cutoff, cutoff);
    CHECK(hard->power().r == Approx(TwoPi * I.r * (1 - std::cos(c))).epsilon(1e-9));
    checkWithin(emittedPower(*hard, 2000, 52), hard->power().r);
    CHECK_THROWS_AS(makeSpotEmitter(toWorld, I, 20, 25), Error);
}

TEST_CASE("directional emitter", "[emitter]") {
    const Spectrum E(3.0);
    const Vec3 dir = normalize(Vec3(1, -2, 0.5));
    const auto e = makeDirectionalEmitter(dir, E);
    e->setSceneBounds({1, 0, 0}, 2.5);
    CHECK(e->isDelta());
    CHECK(e->isInfinite());
    const Vec3 ref{0.5, 0.2, -0.1};
    const DirectSample ds = e->sampleDirect(ref, {0.1, 0.9});
    CHECK(length(ds.wi + dir) < 1e-15);
    CHECK(ds.pdf == 1);
    CHECK(e->pdfDirect(ref, ds.p, ds.n, ds.wi) == 1);
    CHECK(std::isinf(ds.dist));
    CHECK(length(ds.p - Vec3(1, 0, 0)) > 2.5);   // beyond the scene's bounding sphere
    CHECK(ds.value.r == E.r);
    // Emission positions lie on the disk of radius 2.5 perpendicular to dir, upstream of the center.
    Pcg32 rng(61, 0);
    for (int i = 0; i < 1000; ++i) {
        const EmissionSample es = e->sampleEmission(next2(rng), next2(rng));
        const Vec3 off = es.p - Vec3(1, 0, 0);
        REQUIRE(dot(off, dir) == Approx(-2.5).epsilon(1e-12));
        REQUIRE(length(off - dir * dot(off, dir)) <= 2.5 * (1 + 1e-12));
        REQUIRE(length(es.d - dir) < 1e-15);
    }
    checkWithin(emittedPower(*e, 2000, 62), e->power().r);
    CHECK(e->power().r == Approx(E.r * Pi * 2.5 * 2.5).epsilon(1e-12));
}

TEST_CASE("constant emitter", "[emitter]") {
    const Spectrum L(0.5, 1.0, 2.0);
    const auto e = makeConstantEmitter(L);
    e->setSceneBounds({0, 1, 0}, 3);
    const Vec3 ref{0.1, 0.2, 0.3};
    checkDirectConsistency(*e, ref, 2000, 71);
    checkWithin(directDensityIntegral(*e, nullptr, ref, 1000, 72), 1.0);
    // Irradiance on any plane: pi L.
    checkWithin(irradiance(*e, ref, normalize(Vec3(1, 1, 0)), 100000, 73, 2), Pi * L.b);
    CHECK(e->power().g == Approx(L.g * 4 * Pi * Pi * 9).epsilon(1e-12));
    checkWithin(emittedPower(*e, 2000, 74, 1), e->power().g);
}

namespace {

// A scratch directory for the envmap files, removed at the end of the test case.
struct TempDir {
    std::filesystem::path path;
    TempDir() : path(std::filesystem::temp_directory_path() / ("lt_emitter_test_" + std::to_string(getpid()))) {
        std::filesystem::create_directories(path);
    }
    ~TempDir() { std::filesystem::remove_all(path); }
};

} // namespace

TEST_CASE("envmap emitter", "[emitter]") {
    TempDir tmp;
    const int W = 64, H = 32;
    // A dim colored sky, a bright 3x3 spot, two single-texel markers and a distinct top row.
    std::vector<float> rgb(size_t(W) * H * 3);
    auto set = [&](int x, int y, float r, float g, float b) {
        float* p = &rgb[(size_t(y) * W + x) * 3];
        p[0] = r, p[1] = g, p[2] = b;
    };
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) set(x, y, 0.1f + 0.002f * x, 0.2f, 0.05f + 0.01f * y);
    for (int x = 0; x < W; ++x) set(x, 0, 0, 0, 7);
    for (int y = 9; y < 12; ++y)
        for (int x = 39; x < 42; ++x) set(x, y, 60, 50, 40);
    set(0, 15, 0, 3, 0);
    set(16, 15, 0, 0, 4);
    const std::string file = (tmp.path / "sky.exr").string();
    test::writeRgbExr(file, W, H, rgb);

    SECTION("Mitsuba's lat-long mapping: +y is row 0, u = atan2(x, -z) / 2 pi") {
        const auto e = makeEnvmapEmitter(file, Transform(), 2.0);
        CHECK(e->evalEnvironment({0, 1, 0}).b == 14);
        CHECK(e->evalEnvironment(normalize(Vec3(0.01, 0.02, -1))).g == 6);   // u ~ 0.002, row 15
        CHECK(e->evalEnvironment(normalize(Vec3(1, 0.02, 0.01))).b == 8);    // u ~ 0.25, row 15
        // toWorld rotates the map: world = R local.
        const Transform R = Transform::rotate({0, 1, 0}, 90);
        const auto rotated = makeEnvmapEmitter(file, R, 2.0);
        CHECK(rotated->evalEnvironment(R.vector(normalize(Vec3(1, 0.02, 0.01)))).b == 8);
    }

    SECTION("densities, normalization and estimators") {
        const Transform R = Transform::rotate(normalize(Vec3(1, 2, 3)), 40);
        const auto e = makeEnvmapEmitter(file, R, 1.5);
        e->setSceneBounds({0, 0, 1}, 2);
        const Vec3 ref{0.2, 0.1, 0.9};
        checkDirectConsistency(*e, ref, 20000, 81);
        Pcg32 rng(82, 0);
        for (int i = 0; i < 1000; ++i) {
            const DirectSample ds = e->sampleDirect(ref, next2(rng));
            REQUIRE(ds.value == e->evalEnvironment(ds.wi));
        }
        checkWithin(directDensityIntegral(*e, nullptr, ref, 400000, 83), 1.0);
        // Integral of L over the sphere by importance sampling equals power / (pi r^2) exactly in
        // expectation (piecewise-constant radiance).
        Stats sky;
        for (int i = 0; i < 100000; ++i) {
            const DirectSample ds = e->sampleDirect(ref, next2(rng));
            sky.add(ds.pdf > 0 ? ds.value.g / ds.pdf : 0);
        }
        checkWithin(sky, e->power().g / (Pi * 4));
        checkWithin(emittedPower(*e, 100000, 84, 1), e->power().g);
    }

    SECTION("a constant image behaves as the constant emitter") {
        const Spectrum L(0.5, 0.25, 1.0);
        std::vector<float> flat(16 * 8 * 3);
        for (size_t i = 0; i < flat.size(); i += 3) flat[i] = 0.5f, flat[i + 1] = 0.25f, flat[i + 2] = 1.0f;
        const std::string flatFile = (tmp.path / "flat.exr").string();
        test::writeRgbExr(flatFile, 16, 8, flat);
        const auto env = makeEnvmapEmitter(flatFile, Transform(), 1.0);
        const auto cst = makeConstantEmitter(L);
        env->setSceneBounds({0, 0, 0}, 2);
        cst->setSceneBounds({0, 0, 0}, 2);
        Pcg32 rng(91, 0);
        for (int i = 0; i < 1000; ++i) {
            const Vec3 d = warp::squareToUniformSphere(next2(rng));
            REQUIRE(env->evalEnvironment(d) == cst->evalEnvironment(d));
        }
        CHECK(env->power().b == Approx(cst->power().b).epsilon(1e-12));
        checkWithin(directDensityIntegral(*env, nullptr, {}, 100000, 92), 1.0);
        const Vec3 n = normalize(Vec3(0.2, 1, -0.4));
        checkWithin(irradiance(*env, {}, n, 100000, 93, 2), Pi * L.b);
        checkWithin(irradiance(*cst, {}, n, 100000, 94, 2), Pi * L.b);
        checkWithin(emittedPower(*env, 20000, 95, 2), cst->power().b);
    }

    SECTION("bad files: one error line naming the file") {
        std::vector<float> bad = rgb;
        bad[(size_t(2) * W + 3) * 3 + 1] = std::nanf("");
        const std::string nanFile = (tmp.path / "nan.exr").string();
        test::writeRgbExr(nanFile, W, H, bad);
        CHECK_THROWS_WITH(makeEnvmapEmitter(nanFile, Transform(), 1.0), nanFile + ": pixel (3, 2) is NaN or infinite");
        const std::string missing = (tmp.path / "missing.exr").string();
        CHECK_THROWS_WITH(makeEnvmapEmitter(missing, Transform(), 1.0), missing + ": file not found");
        std::vector<float> black(8 * 4 * 3, 0.0f);
        const std::string blackFile = (tmp.path / "black.exr").string();
        test::writeRgbExr(blackFile, 8, 4, black);
        CHECK_THROWS_WITH(makeEnvmapEmitter(blackFile, Transform(), 1.0),
                          blackFile + ": the environment map is completely black");
    }
}

TEST_CASE("a surface vertex takes its shape's emitter, and none on a shape without one", "[emitter]") {
    // A vertex moved from the light onto a wall (HSLT's jumps rebuild vertices in place) must not keep
    // the light: the bidirectional mutation would then take it for a light vertex of emitter -1.
    const auto scene = loadScene(test::shippedScene("cornell-box"));
    int lightShape = -1, plainShape = -1;
    for (size_t i = 0; i < scene->shapes.size(); ++i)
        (scene->shapes[i].emitter >= 0 ? lightShape : plainShape) = int(i);
    REQUIRE(lightShape >= 0);
    REQUIRE(plainShape >= 0);
    PathVertex v;
    for (const int shape : {lightShape, plainShape}) {
        SurfaceInteraction si = scene->shapes[size_t(shape)].surfaceAt(0, Vec2(0.25, 0.25));
        si.shape = shape;
        setSurfaceVertex(*scene, std::move(si), v);
        CHECK(v.emitterIndex == scene->shapes[size_t(shape)].emitter);
        CHECK((v.emitter != nullptr) == (shape == lightShape));
    }
}

TEST_CASE("sky: the Hosek-Wilkie model gives what the authors' reference implementation gives", "[emitter][daylight]") {
    // (turbidity, albedo, solar elevation, theta, gamma) and the RGB radiance of the authors' C code,
    // version 1.1 (arhosek_rgb_skymodelstate_alloc_init + arhosek_tristim_skymodel_radiance), printed with
    // 13 digits: integer and fractional turbidities, turbidity 10 (no upper bracket), both albedo ends,
    // the sun near the horizon and at the zenith, views at the zenith and near the horizon.
    struct Case {
        double turbidity, albedo, elevation, theta, gamma;
        Spectrum expected;
    };
    const Case cases[] = {
        {3, 0.2, 0.6, 0.3, 0.5, {3.669098252319e+00, 5.550981483012e+00, 9.345147952023e+00}},
        {3, 0.2, 0.6, 1.2, 0.1, {3.349389549081e+01, 3.579619143775e+01, 3.533908307716e+01}},
        {1, 0.0, 0.05, 1.5, 1, {7.031682806560e+00, 6.254591992536e+00, 3.119828132563e+00}},
        {10, 1.0, 1.5, 0.1, 2, {6.118863746063e+00, 7.757398710651e+00, 1.366678445215e+01}},
        {4.5, 0.35, 0.9, 0.8, 1.3, {3.708831730143e+00, 6.572906983414e+00, 1.239733355794e+01}},
        {7.25, 0.7, 0.2, 1.45, 0.02, {1.811593253862e+02, 1.248061063834e+02, 5.447397061049e+01}},
        {2, 0.1, 1.0, 0.0, 0.57, {2.320024787486e+00, 4.066853293290e+00, 8.900135312561e+00}},
    };
    for (const Case& c : cases) {
        CAPTURE(c.turbidity, c.albedo, c.elevation, c.theta, c.gamma);
        const Spectrum L = HosekWilkieSky(c.turbidity, Spectrum(c.albedo), c.elevation).radiance(c.theta, c.gamma);
        for (int k = 0; k < 3; ++k)
            CHECK(L[k] == Approx(c.expected[k]).epsilon(1e-11));
    }
}

TEST_CASE("sun position: PSA puts the sun where the solstice and the equinox put it", "[emitter][daylight]") {
    // Greenwich (51.4769 N, 0 E) at the June solstice of 2010 (21 June, 11:28 UT, declination 23.438
    // degrees): at 12:00 UT the sun is due south (the equation of time moves it 0.4 degrees east) at
    // zenith angle latitude - declination (plus 0.002 degrees of parallax).
    const SunLocation greenwich{51.4769, 0, 0};
    SunTime noon{2010, 6, 21, 12, 0, 0};
    const SkyAngles a = sunPosition(noon, greenwich);
    CHECK(radToDeg(a.zenith) == Approx(51.4769 - 23.438).margin(0.03));
    CHECK(radToDeg(a.azimuth) == Approx(180).margin(1.5));
    // The same at 6:00: low in the east-north-east; east is +x of the sky frame, north -z.
    SunTime morning = noon;
    morning.hour = 6;
    const SkyAngles m = sunPosition(morning, greenwich);
    CHECK(radToDeg(m.azimuth) > 60);
    CHECK(radToDeg(m.azimuth) < 90);
    CHECK(skyDirection(m).x > 0.5);
    CHECK(skyDirection(m).y > 0);
    // On the equator at the March equinox of 2010 (20 March, 17:32 UT), at 12:00 local time 90 degrees
    // east of Greenwich (timezone 6): the sun stands almost overhead (declination -0.2 degrees, equation
    // of time 7.5 minutes = 1.9 degrees of hour angle).
    const SkyAngles e = sunPosition({2010, 3, 20, 12, 0, 0}, {0, 90, 6});
    CHECK(radToDeg(e.zenith) < 2.5);
}

TEST_CASE("sun: the Preetham disk dims and reddens toward the horizon, and stays finite", "[emitter][daylight]") {
    double lastLuminance = 1e300, lastRedShare = 0;
    for (double zenithDeg : {0.0, 30.0, 60.0, 80.0, 88.0, 90.0}) {
        const Spectrum L = preethamSunRadiance(degToRad(zenithDeg), 3);
        CAPTURE(zenithDeg, L.r, L.g, L.b);
        REQUIRE(L.isFinite());
        CHECK(L.luminance() < lastLuminance);
        CHECK(L.r / (L.r + L.g + L.b) > lastRedShare);
        lastLuminance = L.luminance();
        lastRedShare = L.r / (L.r + L.g + L.b);
    }
    // More aerosols, less direct sun.
    CHECK(preethamSunRadiance(0.5, 8).luminance() < preethamSunRadiance(0.5, 2).luminance());
}

TEST_CASE("sun: its map holds the disk's irradiance exactly, at any resolution and disk size", "[emitter][daylight]") {
    DaylightSettings d;
    d.sun = {0.6, 2.0};
    d.turbidity = 2.5;
    d.sunScale = 3;
    d.toWorld = Transform::rotate(normalize(Vec3(1, 2, 3)), 40);
    const Spectrum L = preethamSunRadiance(d.sun.zenith, d.turbidity) * d.sunScale;
    const Spectrum E = L * (TwoPi * (1 - std::cos(SunAngularRadius)));
    const Vec3 toSun = normalize(d.toWorld.vector(skyDirection(d.sun)));
    for (int resolution : {64, 512, 2048})
        for (double radiusScale : {1.0, 4.0, 40.0}) {
            CAPTURE(resolution, radiusScale);
            d.resolution = resolution;
            d.sunRadiusScale = radiusScale;
            const auto emitters = makeDaylightEmitters(d, false, true, "sun");
            REQUIRE(emitters.size() == 1);
            Emitter& sun = *emitters[0];
            CHECK(sun.typeName() == "sun");
            sun.setSceneBounds({0, 0, 0}, 1);
            // The integral of the map's radiance over the sphere is E (power = pi r^2 x that integral).
            CHECK(sun.power().g / Pi == Approx(E.g).epsilon(1e-9));
            // Irradiance on a plane facing the sun: E times the mean cosine over the (scaled) disk, within
            // the map's texels (estimated by the emitter's own direct sampling; 5 standard errors).
            const double halfAngle = SunAngularRadius * radiusScale;
            const double meanCos = (1 + std::cos(halfAngle)) / 2;
            const Stats s = irradiance(sun, {0, 0, 0}, toSun, 20000, 101, 1);
            const double texel = 2 * Pi / resolution; // the map's blur of the disk, in radians
            INFO("estimate " << s.mean() << " +- " << s.stdErr() << ", expected " << E.g * meanCos);
            CHECK(std::abs(s.mean() - E.g * meanCos) <= 5 * s.stdErr() + E.g * (1 - std::cos(halfAngle + texel)));
        }
    // Radius scale 0: one directional emitter with that irradiance, light travelling away from the sun.
    d.sunRadiusScale = 0;
    const auto directional = makeDaylightEmitters(d, false, true, "sun");
    REQUIRE(directional.size() == 1);
    CHECK(directional[0]->typeName() == "directional");
    directional[0]->setSceneBounds({0, 0, 0}, 1);
    const DirectSample ds = directional[0]->sampleDirect({0, 0, 0}, {0.5, 0.5});
    CHECK(length(ds.wi - toSun) < 1e-12);
    CHECK(ds.value.g == Approx(E.g).epsilon(1e-9));
}

TEST_CASE("sky: the baked map is the model at its texel centres, turned by toWorld, and the sunsky adds the sun",
          "[emitter][daylight]") {
    DaylightSettings d;
    d.sun = {0.9, 1.0};
    d.resolution = 128;
    d.albedo = Spectrum(0.1, 0.3, 0.5);
    d.skyScale = 2;
    d.toWorld = Transform::rotate(normalize(Vec3(0.3, 1, -0.2)), 70);
    const SkyDome dome(d);
    const auto sky = makeDaylightEmitters(d, true, false, "sky");
    REQUIRE(sky.size() == 1);
    CHECK(sky[0]->typeName() == "sky");
    const int W = 128, H = 64;
    Pcg32 rng(111, 0);
    for (int i = 0; i < 2000; ++i) {
        const int x = int(rng.nextDouble() * W), y = int(rng.nextDouble() * H);
        const SkyAngles centre{(y + 0.5) * Pi / H, (x + 0.5) * TwoPi / W};
        const Vec3 world = d.toWorld.vector(skyDirection(centre));
        CAPTURE(x, y);
        REQUIRE(sky[0]->evalEnvironment(world) == dome.radiance(centre));
        if (y >= H / 2) REQUIRE(sky[0]->evalEnvironment(world).isBlack()); // below the horizon
    }
    // Symmetric about the sun's meridian; brighter toward the sun than away from it at equal height.
    for (double delta : {0.3, 1.1, 2.5}) {
        const Spectrum a = dome.radiance({1.0, d.sun.azimuth + delta}), b = dome.radiance({1.0, d.sun.azimuth - delta});
        CHECK(a.g == Approx(b.g).epsilon(1e-12));
    }
    CHECK(dome.radiance({0.9, d.sun.azimuth + 0.2}).luminance() > dome.radiance({0.9, d.sun.azimuth + Pi}).luminance());
    // extend: the horizon's radiance continues below it, fading to zero at the nadir.
    DaylightSettings extended = d;
    extended.extend = true;
    const SkyDome below(extended);
    CHECK(below.radiance({Pi / 2 + 0.3, 2.0}).g > 0);
    CHECK(below.radiance({Pi - 1e-9, 2.0}).g == Approx(0).margin(1e-12));
    // sunsky: the same sky plus the sun's irradiance in one map.
    d.sunRadiusScale = 2;
    const auto sunsky = makeDaylightEmitters(d, true, true, "sunsky");
    const auto sun = makeDaylightEmitters(d, false, true, "sun");
    REQUIRE(sunsky.size() == 1);
    for (Emitter* e : {sky[0].get(), sunsky[0].get(), sun[0].get()})
        e->setSceneBounds({}, 1);
    CHECK(sunsky[0]->power().b == Approx(sky[0]->power().b + sun[0]->power().b).epsilon(1e-9));
    checkDirectConsistency(*sunsky[0], {0.1, 0.2, 0.3}, 20000, 112);
    checkWithin(emittedPower(*sunsky[0], 100000, 113, 1), sunsky[0]->power().g);
}

TEST_CASE("sky and sun: settings out of range are refused", "[emitter][daylight]") {
    DaylightSettings d;
    d.sun = {0.5, 0};
    auto refused = [&](DaylightSettings bad) {
        return test::errorOf([&] { makeDaylightEmitters(bad, true, true, "sunsky"); });
    };
    DaylightSettings t = d;
    t.turbidity = 11;
    CHECK(refused(t) == "turbidity must be in [1, 10]");
    t.turbidity = std::nan("");
    CHECK(refused(t) == "turbidity must be in [1, 10]");
    DaylightSettings a = d;
    a.albedo = Spectrum(0.2, 1.5, 0.2);
    CHECK(refused(a) == "albedo must be in [0, 1]");
    DaylightSettings st = d;
    st.stretch = 0.5;
    CHECK(refused(st) == "stretch must be in [1, 2]");
    DaylightSettings r = d;
    r.resolution = 1;
    CHECK(refused(r) == "resolution must be in [2, 16384]");
    DaylightSettings below = d;
    below.sun.zenith = 1.7;
    CHECK(refused(below).find("the sun is below the horizon") == 0);
    DaylightSettings huge = d;
    huge.sunRadiusScale = 1000;
    CHECK(refused(huge).find("sunRadiusScale must be in [0, ") == 0);
}
