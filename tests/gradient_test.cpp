// The gradient-domain estimators (libpath/gradient/): the shift mapping's identity and Jacobians, the
// reuse of a two-pixel set against G-PT's pair (T-GR-1), unbiasedness of the primal image and of the
// gradients against path tracing across tile borders (T-GR-3), the furnace (T-GR-4), and the bias of
// Russian roulette without a floor (T-GR-5). Statistical tolerances come from the spread of independent
// runs (Welch's t), never from observed values.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include "bsdf/dielectric.h"
#include "bsdf/diffuse.h"
#include "bsdf/half_vector.h"
#include "bsdf/roughconductor.h"
#include "bsdf/roughdielectric.h"
#include "gdmlt/chain_gradient.h"
#include "gdmlt/chain_stream.h"
#include "gradient/gradient_path_tracer.h"
#include "gradient/path_reusing.h"
#include "math/rng.h"
#include "mcmc/mutation_selection.h"
#include "mcmc/path_space_chains.h"
#include "reconstruct/gradient_image.h"
#include "reconstruct/screened_poisson.h"
#include "sampling/render.h"
#include "scene/scene.h"
#include "chain_runs.h"
#include "test_util.h"
#include "texture/texture.h"

using namespace lt;

namespace {

// A vertex for the half-vector tests: position p, geometric and shading normal n, incident direction wi.
BaseVertex vertexAt(const Bsdf& bsdf, const Vec3& p, const Vec3& n, const Vec3& wi) {
    BaseVertex v;
    v.si.p = p;
    v.si.ng = normalize(n);
    v.si.shading = Frame::fromNormal(v.si.ng);
    v.bsdf = &bsdf;
    v.wi = normalize(wi);
    return v;
}

// A closed diffuse room with a smooth plastic ball, a thin glass pane, a rough metal ball, a point light, a
// spot light and a small area light: delta lobes and delta lights in the shifts.
std::string deltaRoom(const test::TempDir& dir) {
    return dir.write("delta-room.xml", R"(<scene version="0.5.0">
  <integrator type="path"><integer name="maxDepth" value="5"/></integrator>
  <sensor type="perspective"><float name="fov" value="70"/>
    <transform name="toWorld"><lookat origin="0,0,0.9" target="0,-0.1,-1" up="0,1,0"/></transform>
    <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="32"/><rfilter type="box"/></film>
  </sensor>
  <shape type="cube"><boolean name="flipNormals" value="true"/>
    <bsdf type="diffuse"><rgb name="reflectance" value="0.6, 0.5, 0.4"/></bsdf></shape>
  <shape type="sphere"><point name="center" x="-0.4" y="-0.6" z="-0.3"/><float name="radius" value="0.35"/>
    <bsdf type="plastic"><rgb name="diffuseReflectance" value="0.2, 0.4, 0.7"/></bsdf></shape>
  <shape type="sphere"><point name="center" x="0.45" y="-0.65" z="-0.5"/><float name="radius" value="0.3"/>
    <bsdf type="roughconductor"><float name="alpha" value="0.15"/></bsdf></shape>
  <shape type="rectangle">
    <transform name="toWorld"><scale x="0.3" y="0.5"/><rotate y="1" angle="30"/><translate x="0.1" y="-0.3" z="0.1"/></transform>
    <bsdf type="thindielectric"/></shape>
  <emitter type="point"><point name="position" x="0.3" y="0.7" z="0"/><rgb name="intensity" value="2"/></emitter>
  <emitter type="spot"><transform name="toWorld"><lookat origin="-0.7,0.8,0.5" target="-0.4,-0.6,-0.3"/></transform>
    <rgb name="intensity" value="4"/><float name="cutoffAngle" value="25"/></emitter>
  <shape type="sphere"><point name="center" x="-0.6" y="0.85" z="-0.6"/><float name="radius" value="0.08"/>
    <emitter type="area"><rgb name="radiance" value="20"/></emitter></shape>
</scene>)");
}

// A diffuse floor in a room of smooth plastic, seen from above, lit by a point light and a small area light:
// paths from the floor meet plastic that takes its delta coat but samples the lights through its diffuse
// base (the light ending a reconnection reaches while the path follows the coat).
std::string plasticRoom(const test::TempDir& dir) {
    return dir.write("plastic-room.xml", R"(<scene version="0.5.0">
  <integrator type="path"><integer name="maxDepth" value="4"/></integrator>
  <sensor type="perspective"><float name="fov" value="60"/>
    <transform name="toWorld"><lookat origin="0,0.6,0.2" target="0,-1,0" up="0,0,-1"/></transform>
    <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="32"/><rfilter type="box"/></film>
  </sensor>
  <shape type="cube"><boolean name="flipNormals" value="true"/>
    <bsdf type="plastic"><rgb name="diffuseReflectance" value="0.5, 0.4, 0.3"/></bsdf></shape>
  <shape type="rectangle">
    <transform name="toWorld"><scale value="0.99"/><rotate x="1" angle="-90"/><translate y="-0.98"/></transform>
    <bsdf type="diffuse"><rgb name="reflectance" value="0.6"/></bsdf></shape>
  <emitter type="point"><point name="position" x="0.3" y="0.5" z="0.2"/><rgb name="intensity" value="2"/></emitter>
  <shape type="sphere"><point name="center" x="-0.5" y="0.7" z="-0.4"/><float name="radius" value="0.1"/>
    <emitter type="area"><rgb name="radiance" value="10"/></emitter></shape>
</scene>)");
}

// Directions on the unit sphere: the solid angle of the small triangle (a, b, c), by the cross product.
double smallSolidAngle(const Vec3& a, const Vec3& b, const Vec3& c) { return 0.5 * length(cross(b - a, c - a)); }

GradientSettings settingsFor(const Scene& scene) {
    GradientSettings gs;
    gs.paths.maxDepth = scene.integrator.maxDepth;
    gs.paths.rrDepth = scene.integrator.rrDepth;
    return gs;
}

// One gradient-domain render: the planes as a gradient image (primal, dx, dy, direct).
GradientImage renderGradient(const Scene& scene, const PixelEstimator& estimator, int spp, uint64_t seed) {
    SampleFilm film(scene.camera, estimator.planes());
    RenderSettings rs;
    rs.spp = spp;
    rs.seed = seed;
    const RenderStats st = render(scene, estimator, rs, film, RunControl(2));
    REQUIRE(st.health.nonFinite == 0);
    return gradientImageFromBuffer(film.toBuffer(), "test");
}

std::vector<float> renderWith(test::PixelMethod method, const Scene& scene, int spp, uint64_t seed) {
    SampleFilm film(scene.camera);
    RenderSettings rs;
    rs.paths = settingsFor(scene).paths;
    rs.spp = spp;
    rs.seed = seed;
    (void)render(scene, *test::makePixelEstimator(method, scene, rs.paths), rs, film, RunControl(2));
    return film.develop();
}

std::vector<float> renderPt(const Scene& scene, int spp, uint64_t seed) {
    return renderWith(test::PixelMethod::PathTracing, scene, spp, seed);
}

// Mean luminance over square regions of `r` pixels of an image given per pixel (RGB at index i).
template <class F> std::vector<double> regionMeans(int w, int h, int r, F&& rgb) {
    const int rx = w / r, ry = h / r;
    std::vector<double> out(size_t(rx * ry), 0.0);
    for (int y = 0; y < ry * r; ++y)
        for (int x = 0; x < rx * r; ++x)
            out[size_t((y / r) * rx + x / r)] += rgb(x, y).luminance() / double(r * r);
    return out;
}

struct MeanVar {
    double mean = 0, var = 0;
};

MeanVar meanVar(const std::vector<std::vector<double>>& runs, size_t k) {
    MeanVar m;
    for (const auto& r : runs)
        m.mean += r[k] / double(runs.size());
    for (const auto& r : runs)
        m.var += (r[k] - m.mean) * (r[k] - m.mean) / double(runs.size() - 1);
    return m;
}

// Welch's test, region by region: |mean_a - mean_b| < 5 standard errors (about 10 degrees of freedom: a false
// failure has probability ~5e-4 per region).
void checkSameMeans(const std::vector<std::vector<double>>& a, const std::vector<std::vector<double>>& b) {
    for (size_t k = 0; k < a[0].size(); ++k) {
        CAPTURE(k);
        const MeanVar ma = meanVar(a, k), mb = meanVar(b, k);
        const double se = std::sqrt(ma.var / double(a.size()) + mb.var / double(b.size()));
        CAPTURE(ma.mean, mb.mean, se);
        CHECK(std::abs(ma.mean - mb.mean) <= 5 * se);
    }
}

Spectrum at(const RgbPlanes& p, uint32_t w, int x, int y) {
    const size_t i = size_t(y) * w + size_t(x);
    return {p[0][i], p[1][i], p[2][i]};
}

} // namespace

TEST_CASE("a base path shifted onto its own primary hit is itself", "[gradient]") {
    for (const char* name : {"cornell-box", "veach-mis", "glass-box", "caustic-mirror"}) {
        CAPTURE(name);
        const auto scene = loadScene(test::shippedScene(name));
        const Vec3 eye = scene->camera.position(); // a pinhole: its one lens point
        const GradientSettings gs = settingsFor(*scene);
        Pcg32 rng(7, 1);
        const auto& f = scene->camera.film();
        int compared = 0, differentPaths = 0;
        const int paths = 400;
        for (int n = 0; n < paths; ++n) {
            const Vec2 raster(f.cropX + rng.nextDouble() * f.cropWidth, f.cropY + rng.nextDouble() * f.cropHeight);
            IndependentSampler sampler(uint64_t(n) + 1, 3);
            const BasePath base = traceBasePath(*scene, gs.paths, gs.shiftThreshold, raster, eye,
                                                primaryVertex(*scene, raster, eye), sampler);
            const auto own = baseEndingTerms(*scene, base);
            std::vector<EndingTerm> shifted;
            (void)shiftBasePath(*scene, base, primaryVertex(*scene, raster, eye), gs.shiftThreshold, shifted,
                                EarlyOut::Never);
            REQUIRE(shifted.size() == own.size());
            bool pathSame = true;
            for (size_t e = 0; e < own.size(); ++e) {
                if (own[e].density == 0) continue;
                ++compared;
                // A reconnection recomputes the direction from hit points with float barycentrics, which turns it
                // by up to ~1e-3 (bsdf/bsdf.h DeltaDirectionTolerance); near grazing the cosines change by
                // about a percent.
                const double tol = 2e-2 * (own[e].value.maxValue() + 1e-12);
                bool same = std::abs(shifted[e].density - own[e].density) <= 2e-2 * own[e].density;
                for (int c = 0; c < 3; ++c)
                    same = same && std::abs(shifted[e].value[c] - own[e].value[c]) <= tol;
                pathSame = pathSame && same;
            }
            differentPaths += !pathSame;
        }
        CAPTURE(compared, differentPaths);
        CHECK(compared > 400);
        // A reconnection's shadow ray between the points of one traced ray can, very rarely, graze a neighbour; and
        // a direction turned by at most 1e-3 (see above) changes a cosine c by up to 1e-3 / c relative, beyond
        // the 2 % only for c < 0.05, which a direction drawn in proportion to the cosine has with probability
        // c^2 = 1/400 at each reconnected vertex, and only when its turn is near the bound (the compiler's
        // rounding decides which paths). Such a base path differs in every ending term after that vertex, so the
        // rare event is counted per path: at most 1 in 200.
        CHECK(differentPaths <= paths / 200);
    }
}

TEST_CASE("the early out leaves every pixel's share of a base path as it was, bit for bit", "[gradient]") {
    // Over sets of 3 x 3 pixels (path reusing's tiles), each base path's shares with the early out taken and
    // with every shift followed to its end. door-ajar is lit through a gap: most tails carry nothing.
    test::TempDir dir;
    for (const char* name : {"door-ajar", "delta-room", "veach-mis"}) {
        CAPTURE(name);
        const auto scene = loadScene(std::string(name) == "delta-room" ? deltaRoom(dir) : test::shippedScene(name));
        const Vec3 eye = scene->camera.position(); // a pinhole: its one lens point
        scene->camera = scene->camera.withResolution(64, 48);
        const GradientSettings gs = settingsFor(*scene);
        Pcg32 rng(11, 2);
        int earlyOuts = 0, carrying = 0;
        for (int n = 0; n < 400; ++n) {
            const Vec2 corner(double(1 + rng.nextUInt() % 60), double(1 + rng.nextUInt() % 44)), offset(rng.nextDouble(), rng.nextDouble());
            std::vector<std::optional<BaseVertex>> primary;
            for (int j = 0; j < 9; ++j)
                primary.push_back(primaryVertex(*scene, corner + Vec2(double(j % 3), double(j / 3)) + offset, eye));
            const size_t k = rng.nextUInt() % 9;
            IndependentSampler sampler(uint64_t(n), 4);
            const BasePath base =
                traceBasePath(*scene, gs.paths, gs.shiftThreshold, corner + Vec2(double(k % 3), double(k / 3)) + offset,
                              eye, primary[k], sampler);
            std::vector<std::vector<EndingTerm>> taken(9), followed(9);
            for (size_t m = 0; m < 9; ++m) {
                if (m == k) {
                    taken[m] = followed[m] = baseEndingTerms(*scene, base);
                    continue;
                }
                earlyOuts += shiftBasePath(*scene, base, primary[m], gs.shiftThreshold, taken[m]).cause ==
                             ShiftCause::EarlyOut;
                (void)shiftBasePath(*scene, base, primary[m], gs.shiftThreshold, followed[m], EarlyOut::Never);
            }
            std::vector<const std::vector<EndingTerm>*> a, b;
            for (size_t m = 0; m < 9; ++m) {
                a.push_back(&taken[m]);
                b.push_back(&followed[m]);
            }
            std::vector<Spectrum> shareTaken(9), shareFollowed(9);
            REQUIRE(shareOverPixels(a, shareTaken) == shareOverPixels(b, shareFollowed));
            for (size_t m = 0; m < 9; ++m) {
                CAPTURE(n, m);
                carrying += !shareFollowed[m].isBlack();
                for (int c = 0; c < 3; ++c)
                    CHECK(shareTaken[m][c] == shareFollowed[m][c]);
            }
        }
        // The test must see the early out taken (delta-room's point lights light most tails: fewer there).
        CAPTURE(earlyOuts, carrying);
        CHECK(earlyOuts > 20);
        CHECK(carrying > 100);
    }
}

TEST_CASE("the half-vector copy's Jacobian is the solid-angle ratio of finite differences", "[gradient]") {
    const auto white = std::make_shared<ConstantTexture>(Spectrum(0.8));
    const Diffuse diffuse(DiffuseParams{white});
    RoughConductorParams rc;
    rc.alphaU = rc.alphaV = 0.1;
    const RoughConductor conductor(rc);
    RoughDielectricParams rd;
    rd.alphaU = rd.alphaV = 0.2;
    const RoughDielectric glass(rd);
    struct Case {
        const char* name;
        const Bsdf* bsdf;
        Vec3 wiX, woX, wiY; // world; x has normal +z, y a tilted normal
    };
    // 85 degrees from the normal. Each pair (wiX, woX) is one the BSDF samples: its half vector faces both
    // directions as a microfacet must (a refraction from grazing incidence leaves at about 42 degrees).
    const Vec3 grazing = normalize(Vec3(1, 0, 0.09));
    const std::vector<Case> cases = {
        {"diffuse", &diffuse, Vec3(0.3, 0.1, 1), Vec3(-0.5, 0.2, 1), Vec3(0.25, 0.15, 1)},
        {"glossy reflection", &conductor, Vec3(0.3, 0.1, 1), Vec3(-0.35, -0.05, 1), Vec3(0.25, 0.2, 1)},
        {"glossy reflection, grazing", &conductor, grazing, Vec3(-1, 0.02, 0.1), Vec3(1, 0.05, 0.12)},
        {"refraction into glass", &glass, Vec3(0.3, 0.1, 1), Vec3(-0.2, -0.05, -1), Vec3(0.25, 0.2, 1)},
        {"refraction out of glass", &glass, Vec3(0.1, 0.05, -1), Vec3(-0.2, -0.1, 1), Vec3(0.12, 0.0, -1)},
        {"refraction, grazing incidence", &glass, grazing, Vec3(-0.66, 0.02, -0.75), Vec3(1, 0.03, 0.1)},
    };
    for (const auto& c : cases) {
        CAPTURE(c.name);
        const BaseVertex x = vertexAt(*c.bsdf, Vec3(0, 0, 0), Vec3(0, 0, 1), c.wiX);
        const BaseVertex y = vertexAt(*c.bsdf, Vec3(0.1, 0, 0), Vec3(0.15, -0.05, 1), c.wiY);
        const Vec3 wo = normalize(c.woX);
        const auto base = copyHalfVector(x, x.wi, wo, false, y);
        REQUIRE(base);
        CHECK(base->jacobian > 0);
        // A small triangle of directions around wo and its image.
        const Frame around = Frame::fromNormal(wo);
        const double eps = 1e-5;
        const Vec3 a = wo, b = normalize(wo + eps * around.s), d = normalize(wo + eps * around.t);
        const auto ya = copyHalfVector(x, x.wi, a, false, y), yb = copyHalfVector(x, x.wi, b, false, y),
                   yd = copyHalfVector(x, x.wi, d, false, y);
        REQUIRE((ya && yb && yd));
        const double fd = smallSolidAngle(ya->wo, yb->wo, yd->wo) / smallSolidAngle(a, b, d);
        CAPTURE(fd, base->jacobian);
        CHECK(base->jacobian == Approx(fd).epsilon(1e-3));
        // The inverse shift: copying y's half vector back to x gives x's direction, with the inverse Jacobian
        // (the shift is a bijection, Kettunen et al. 2015, Sec. 5).
        const auto back = copyHalfVector(y, y.wi, base->wo, false, x);
        REQUIRE(back);
        CHECK(length(back->wo - wo) < 1e-9);
        CHECK(base->jacobian * back->jacobian == Approx(1).epsilon(1e-9));
    }
    SECTION("a delta lobe copies to the specular direction with Jacobian 1, and fails where it has no solution") {
        const Dielectric smooth(DielectricParams{});
        const BaseVertex x = vertexAt(smooth, Vec3(0, 0, 0), Vec3(0, 0, 1), Vec3(0.3, 0.1, 1));
        const BaseVertex y = vertexAt(smooth, Vec3(0.1, 0, 0), Vec3(0.1, 0, 1), Vec3(-0.2, 0.3, 1));
        const Vec3 mirror = normalize(Vec3(-0.3, -0.1, 1));
        const auto r = copyHalfVector(x, x.wi, mirror, true, y);
        REQUIRE(r);
        CHECK(r->jacobian == 1);
        const Vec3 n = y.si.ng;
        CHECK(length(r->wo - (2 * dot(y.wi, n) * n - y.wi)) < 1e-9);
        // A smooth refraction copied to y and back, at the tilted normal: the base direction again.
        const Vec3 into = *refract(x.wi, x.si.ng, 1.5046 / 1.000277);
        const BaseVertex tilted = vertexAt(smooth, Vec3(0.1, 0, 0), Vec3(0.2, -0.1, 1), Vec3(-0.2, 0.3, 1));
        const auto there = copyHalfVector(x, x.wi, into, true, tilted);
        REQUIRE(there);
        CHECK(dot(there->wo, tilted.si.ng) < 0);
        const auto back = copyHalfVector(tilted, tilted.wi, there->wo, true, x);
        REQUIRE(back);
        CHECK(length(back->wo - into) < 1e-9);
        // From inside the glass at a grazing angle the refraction out has no solution (total internal
        // reflection): the copy of a refraction fails.
        const BaseVertex in = vertexAt(smooth, Vec3(0, 0, 0), Vec3(0, 0, 1), Vec3(0.1, 0, -1));
        const auto out = refract(in.wi, Vec3(0, 0, 1), 1.000277 / 1.5046);
        REQUIRE(out);
        const BaseVertex tir = vertexAt(smooth, Vec3(0.1, 0, 0), Vec3(0, 0, 1), Vec3(1, 0, -0.2));
        CHECK_FALSE(copyHalfVector(in, in.wi, *out, true, tir));
    }
}

TEST_CASE("the reconnection Jacobian is the solid-angle ratio of finite differences, grazing included", "[gradient]") {
    // Directions from the base vertex x around the one toward z hit the plane through z; the offset vertex y
    // sees those points under other directions. Their solid angles' ratio is d omega_y / d omega_x.
    struct Case {
        const char* name;
        Vec3 x, y, z, n;
    };
    const std::vector<Case> cases = {
        {"facing", Vec3(0, 0, 0), Vec3(0.3, 0.1, 0), Vec3(0.2, 0.1, 2), normalize(Vec3(0.1, 0, -1))},
        {"oblique", Vec3(0, 0, 0), Vec3(-0.5, 0.4, 0.3), Vec3(1, 0.5, 1.5), normalize(Vec3(-0.6, 0.2, -0.5))},
        {"grazing at z for x", Vec3(0, 0, 0), Vec3(0.2, -0.3, 0.5), Vec3(1, 0, 1), normalize(Vec3(0.05, 1, 0.02))},
        {"far offset", Vec3(0, 0, 0), Vec3(3, 1, -1), Vec3(0.5, 0.2, 2), normalize(Vec3(0, 0.3, -1))},
    };
    for (const auto& c : cases) {
        CAPTURE(c.name);
        const Vec3 d = normalize(c.z - c.x);
        const Frame around = Frame::fromNormal(d);
        const double eps = 1e-6;
        auto onPlane = [&](const Vec3& dir) { return c.x + dir * (dot(c.z - c.x, c.n) / dot(dir, c.n)); };
        const Vec3 a = d, b = normalize(d + eps * around.s), e = normalize(d + eps * around.t);
        const Vec3 pa = onPlane(a), pb = onPlane(b), pe = onPlane(e);
        const double fd =
            smallSolidAngle(normalize(pa - c.y), normalize(pb - c.y), normalize(pe - c.y)) / smallSolidAngle(a, b, e);
        CAPTURE(fd);
        CHECK(reconnectionJacobian(c.y, c.x, c.z, c.n) == Approx(fd).epsilon(1e-4));
    }
    // The base direction exactly in the plane: no density in solid angle, no offset technique.
    CHECK(reconnectionJacobian(Vec3(0, 1, 0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)) == 0);
}

TEST_CASE("T-GR-1: reusing the paths of a two-pixel set is G-PT's pair estimator, bit for bit", "[gradient]") {
    const auto scene = loadScene(test::shippedScene("veach-mis"));
    const Vec3 eye = scene->camera.position(); // a pinhole: its one lens point
    scene->camera = scene->camera.withResolution(40, 30);
    const GradientSettings gs = settingsFor(*scene);
    for (int n = 0; n < 50; ++n) {
        CAPTURE(n);
        const Vec2 offset(0.5 + 0.3 * std::sin(n), 0.5 + 0.3 * std::cos(n));
        const Vec2 p(5 + n % 30, 5 + n % 20);
        std::vector<std::optional<BaseVertex>> primary = {primaryVertex(*scene, p + offset, eye),
                                                          primaryVertex(*scene, p + Vec2(1, 0) + offset, eye)};
        std::vector<BasePath> bases;
        for (size_t k = 0; k < 2; ++k) {
            IndependentSampler sampler(uint64_t(100 + n), k);
            bases.push_back(traceBasePath(*scene, gs.paths, gs.shiftThreshold, p + Vec2(double(k), 0) + offset, eye,
                                          primary[k], sampler));
        }
        SampleHealth health;
        const auto reused = reuseBasePaths(*scene, gs.shiftThreshold, primary, bases, {1.0, 1.0}, nullptr, health);
        // G-PT: each base path with its one neighbour, weights p_i / (p_i + p_j |T'|) (Kettunen et al. Eq. 8).
        std::vector<Spectrum> pair(2);
        std::vector<EndingTerm> shifted;
        const auto own0 = baseEndingTerms(*scene, bases[0]), own1 = baseEndingTerms(*scene, bases[1]);
        if (!bases[0].vertices.empty()) {
            (void)shiftBasePath(*scene, bases[0], primary[1], gs.shiftThreshold, shifted);
            REQUIRE(shareOverPixels({&own0, &shifted}, pair));
        }
        if (!bases[1].vertices.empty()) {
            (void)shiftBasePath(*scene, bases[1], primary[0], gs.shiftThreshold, shifted);
            REQUIRE(shareOverPixels({&shifted, &own1}, pair));
        }
        for (int c = 0; c < 3; ++c) {
            CHECK(reused[0][c] == pair[0][c]);
            CHECK(reused[1][c] == pair[1][c]);
        }
    }
}

TEST_CASE("T-GR-3: G-PT and path reusing are unbiased: primal and gradients against path tracing", "[gradient][long]") {
    // A diffuse scene, one with glossy plates and small lights, one with glass (half-vector copies), and one
    // with delta lights, smooth plastic and a thin pane.
    test::TempDir dir;
    for (const char* name : {"cornell-box", "veach-mis", "glass-box", "delta-room"}) {
        CAPTURE(name);
        const auto scene = loadScene(std::string(name) == "delta-room" ? deltaRoom(dir) : test::shippedScene(name));
        scene->camera = scene->camera.withResolution(32, 32);
        const GradientSettings gs = settingsFor(*scene);
        const int runs = 16, w = 32, r = 8;
        // Per run: region means of the image, of its horizontal and vertical forward differences, and of its
        // L2 reconstruction (lt-gradient | lt-reconstruct --norm l2: linear in the estimates, so unbiased too;
        // exact here, Ceres's Cholesky at 32 x 32).
        auto gradientRuns = [&](const PixelEstimator& est, int spp) {
            std::array<std::vector<std::vector<double>>, 4> out;
            for (int run = 0; run < runs; ++run) {
                const GradientImage g = renderGradient(*scene, est, spp, 10 + uint64_t(run));
                auto image = [&](int x, int y) { return at(g.primal, g.width, x, y) + at(*g.direct, g.width, x, y); };
                out[0].push_back(regionMeans(w, w, r, image));
                // dx plus the differences of the direct plane: the differences of the whole image.
                out[1].push_back(regionMeans(w - 1, w, r, [&](int x, int y) {
                    return at(g.dx, g.width, x, y) + image(x + 1, y) - image(x, y) - at(g.primal, g.width, x + 1, y) +
                           at(g.primal, g.width, x, y);
                }));
                out[2].push_back(regionMeans(w, w - 1, r, [&](int x, int y) {
                    return at(g.dy, g.width, x, y) + image(x, y + 1) - image(x, y) - at(g.primal, g.width, x, y + 1) +
                           at(g.primal, g.width, x, y);
                }));
                ReconstructStatistics stats;
                const file::Buffer l2 = reconstructScreenedPoisson(g, ReconstructSettings{}, stats);
                out[3].push_back(regionMeans(w, w, r, [&](int x, int y) {
                    const size_t i = size_t(y * w + x);
                    return Spectrum(l2.planes[0][i], l2.planes[1][i], l2.planes[2][i]);
                }));
            }
            return out;
        };
        std::array<std::vector<std::vector<double>>, 3> pt;
        for (int run = 0; run < runs; ++run) {
            const auto img = renderPt(*scene, 16, 500 + uint64_t(run));
            auto px = [&](int x, int y) {
                const size_t i = size_t(y * w + x);
                return Spectrum(img[3 * i], img[3 * i + 1], img[3 * i + 2]);
            };
            pt[0].push_back(regionMeans(w, w, r, px));
            pt[1].push_back(regionMeans(w - 1, w, r, [&](int x, int y) { return px(x + 1, y) - px(x, y); }));
            pt[2].push_back(regionMeans(w, w - 1, r, [&](int x, int y) { return px(x, y + 1) - px(x, y); }));
        }
        {
            INFO("G-PT");
            const auto g = gradientRuns(GradientPathTracer(*scene, gs), 8);
            for (int p = 0; p < 3; ++p) {
                CAPTURE(p);
                checkSameMeans(g[size_t(p)], pt[size_t(p)]);
            }
            INFO("the L2 reconstruction");
            checkSameMeans(g[3], pt[0]);
        }
        for (int tile : {1, 3, 6, 10}) {
            INFO("path reusing, tile " << tile);
            GradientSettings t = gs;
            t.tile = tile;
            const auto g = gradientRuns(PathReusing(*scene, t), 8);
            for (int p = 0; p < 3; ++p) {
                CAPTURE(p);
                checkSameMeans(g[size_t(p)], pt[size_t(p)]);
            }
            INFO("the L2 reconstruction");
            checkSameMeans(g[3], pt[0]);
        }
    }
}

TEST_CASE("through a window at low sample counts the default reconstructions keep the primal's mean",
          "[gradient][long]") {
    // window-room: a closed room lit through one window by a sky with a small sun, unbounded depth, G-PT and path
    // reusing at 2 samples a pixel, where rare bright paths (the sun's patch seen after bounces) make fireflies. L2
    // keeps the primal's mean exactly and L1 with its default restoration too (screened_poisson.h): each run's shift
    // under 1e-4. Region by region (16 pixels, the restoring kernel's own size, so L1's detail bias below it is not
    // averaged away), the primal, L2 and L1 must match path tracing within the spread of independent runs
    // (checkSameMeans). Broken on purpose: L1 without the restoration (MeanRestoration::Free) moved G-PT's image mean
    // by -23 % (path reusing's by -1.1 %: its tiles share every path, so its fireflies are spread before the solve),
    // which the last check requires; with it, the per-run check of the shift fails.
    const auto scene = loadScene(test::shippedScene("window-room"));
    scene->camera = scene->camera.withResolution(48, 32);
    scene->integrator.maxDepth = -1;
    const GradientSettings gs = settingsFor(*scene);
    const int runs = 12, w = 48, h = 32, r = 16;
    std::vector<std::vector<double>> pt;
    for (int run = 0; run < runs; ++run) {
        const auto img = renderPt(*scene, 8, 700 + uint64_t(run));
        pt.push_back(regionMeans(w, h, r, [&](int x, int y) {
            const size_t i = size_t(y * w + x);
            return Spectrum(img[3 * i], img[3 * i + 1], img[3 * i + 2]);
        }));
    }
    const auto check = [&](const PixelEstimator& estimator) {
        std::array<std::vector<std::vector<double>>, 3> regions; // primal + direct, L2, L1
        double freeShift = 0;
        for (int run = 0; run < runs; ++run) {
            const GradientImage g = renderGradient(*scene, estimator, 2, 30 + uint64_t(run));
            regions[0].push_back(regionMeans(
                w, h, r, [&](int x, int y) { return at(g.primal, g.width, x, y) + at(*g.direct, g.width, x, y); }));
            ReconstructSettings s;
            for (int k = 1; k < 3; ++k) {
                s.norm = k == 1 ? ReconstructNorm::L2 : ReconstructNorm::L1;
                ReconstructStatistics stats;
                const file::Buffer b = reconstructScreenedPoisson(g, s, stats);
                regions[size_t(k)].push_back(regionMeans(w, h, r, [&](int x, int y) {
                    const size_t i = size_t(y * w + x);
                    return Spectrum(b.planes[0][i], b.planes[1][i], b.planes[2][i]);
                }));
                // The image mean is the primal's: exact up to the float storage (every solve here is Ceres's Cholesky).
                CHECK(std::abs(stats.meanShift) < 1e-4);
            }
            s.mean = MeanRestoration::Free;
            ReconstructStatistics free;
            (void)reconstructScreenedPoisson(g, s, free);
            freeShift += free.meanShift / runs;
        }
        for (int k = 0; k < 3; ++k) {
            CAPTURE(k);
            checkSameMeans(regions[size_t(k)], pt);
        }
        return freeShift;
    };
    double freeShift = 0;
    {
        INFO("G-PT");
        freeShift = check(GradientPathTracer(*scene, gs));
    }
    {
        INFO("path reusing");
        (void)check(PathReusing(*scene, gs));
    }
    // The case of the test: at 2 samples a pixel G-PT's fireflies are enough for L1 alone to move the mean.
    INFO("L1 without the restoration moved G-PT's mean by " << 100 * freeShift << " %");
    CHECK(freeShift < -0.05);
}

TEST_CASE("T-GR-4: in the furnace every gradient is zero in expectation, at tile borders too", "[gradient]") {
    test::TempDir dir;
    const auto scene = loadScene(test::furnaceBox(dir, 0.5, 4));
    const GradientSettings gs = settingsFor(*scene);
    // Le * (1 + rho + rho^2 + rho^3) with the directly seen emission in the direct plane.
    const double expected = 1 + 0.5 + 0.25 + 0.125;
    for (int tile : {0, 3, 5}) { // 0: G-PT
        CAPTURE(tile);
        GradientSettings t = gs;
        t.tile = tile;
        const GradientImage g = tile == 0 ? renderGradient(*scene, GradientPathTracer(*scene, t), 16, 3)
                                          : renderGradient(*scene, PathReusing(*scene, t), 16, 3);
        // Every pixel estimates the same values: the spread over the pixels gives the standard errors. The
        // tile grid moves every pass, so tile borders would show as a bias of the columns' and rows' means;
        // the image's mean gradient is their sum.
        double sp = 0, sp2 = 0, sx = 0, sx2 = 0, sy = 0, sy2 = 0;
        size_t n = 0, ng = 0;
        for (int y = 0; y < int(g.height); ++y)
            for (int x = 0; x < int(g.width); ++x) {
                const double v = (at(g.primal, g.width, x, y) + at(*g.direct, g.width, x, y)).luminance();
                sp += v;
                sp2 += v * v;
                ++n;
                if (x + 1 < int(g.width) && y + 1 < int(g.height)) {
                    const double dx = at(g.dx, g.width, x, y).luminance(), dy = at(g.dy, g.width, x, y).luminance();
                    sx += dx;
                    sx2 += dx * dx;
                    sy += dy;
                    sy2 += dy * dy;
                    ++ng;
                }
            }
        auto se = [](double s, double s2, size_t k) {
            const double m = s / double(k);
            return std::sqrt(std::max(0.0, s2 / double(k) - m * m) / double(k - 1));
        };
        CAPTURE(sp / double(n), sx / double(ng), sy / double(ng));
        CHECK(std::abs(sp / double(n) - expected) <= 5 * se(sp, sp2, n));
        CHECK(std::abs(sx / double(ng)) <= 5 * se(sx, sx2, ng) + 1e-12);
        CHECK(std::abs(sy / double(ng)) <= 5 * se(sy, sy2, ng) + 1e-12);
    }
}

TEST_CASE("T-GR-5: path reusing's Russian roulette without a floor is biased where black base paths shift to light",
          "[gradient]") {
    // A floor of one-pixel black and white checks under a uniform sky, seen from above: a black check's base
    // path carries nothing, its shift onto a white neighbour does. Without the floor q_min those base paths
    // never survive and their share of the white pixels is lost; with it nothing is.
    test::TempDir dir;
    const std::string xml = dir.write("checks.xml", R"(<scene version="0.5.0">
  <integrator type="path"><integer name="maxDepth" value="2"/></integrator>
  <sensor type="perspective"><float name="fov" value="40"/>
    <transform name="toWorld"><lookat origin="0,0,3" target="0,0,0" up="0,1,0"/></transform>
    <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="24"/>
      <rfilter type="box"/></film>
  </sensor>
  <shape type="rectangle">
    <bsdf type="diffuse"><texture type="checkerboard" name="reflectance">
      <rgb name="color0" value="0.8"/><rgb name="color1" value="0"/>
      <float name="uscale" value="6"/><float name="vscale" value="6"/></texture></bsdf>
  </shape>
  <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
</scene>)");
    const auto scene = loadScene(xml);
    GradientSettings gs = settingsFor(*scene);
    gs.tile = 4;
    const int runs = 6;
    std::vector<std::vector<double>> pt, floor0, floor01;
    for (int run = 0; run < runs; ++run) {
        const auto img = renderPt(*scene, 16, 900 + uint64_t(run));
        pt.push_back(regionMeans(24, 24, 24, [&](int x, int y) {
            const size_t i = size_t(y * 24 + x);
            return Spectrum(img[3 * i], img[3 * i + 1], img[3 * i + 2]);
        }));
        for (double qmin : {0.0, 0.1}) {
            GradientSettings t = gs;
            t.rrMin = qmin;
            const GradientImage g = renderGradient(*scene, PathReusing(*scene, t), 16, 40 + uint64_t(run));
            (qmin == 0 ? floor0 : floor01).push_back(regionMeans(24, 24, 24, [&](int x, int y) {
                return at(g.primal, g.width, x, y) + at(*g.direct, g.width, x, y);
            }));
        }
    }
    checkSameMeans(floor01, pt);
    const MeanVar a = meanVar(floor0, 0), b = meanVar(pt, 0);
    CAPTURE(a.mean, b.mean);
    CHECK(b.mean - a.mean > 5 * std::sqrt(a.var / runs + b.var / runs));
}

namespace {

// The path of pixel m that the shift of base path x (pixel k) onto m's primary vertex produces when it
// reconnects at the primary hit: m's primary vertex, then x's vertices from x_2 on, with m's own sampling
// factors where its direction differs, its own light sample toward x's point on the light, and no Russian
// roulette (the scene's rrDepth lies beyond the path).
BasePath reconnectedPath(const Scene& scene, const BasePath& x, const BaseVertex& primary) {
    BasePath y = x;
    BaseVertex& y1 = y.vertices[0];
    const BaseVertex& x1 = x.vertices[0];
    y1.si = primary.si;
    y1.wi = primary.wi;
    y1.bsdf = primary.bsdf;
    y1.emitter = primary.emitter;
    auto scatter = [](BaseVertex& v, const Vec3& wo) {
        const WorldBsdf wb = v.worldBsdf();
        v.wo = wo;
        v.fCos = wb.eval(v.wi, wo, Transport::Radiance) * std::abs(dot(wo, v.si.ng));
        v.pdf = wb.pdf(v.wi, wo);
    };
    if (x1.scattered) scatter(y1, normalize(x.vertices[1].si.p - y1.si.p));
    if (x1.light.emitter >= 0) {
        BaseLightSample& l = y1.light;
        const Emitter& em = *scene.emitters[size_t(l.emitter)];
        REQUIRE(!l.infinite);
        l.wo = normalize(l.p - y1.si.p);
        if (l.delta) { // point and spot lights: intensity over the squared distance, density 1 x pmf
            l.Le = em.intensity(-l.wo) / lengthSquared(l.p - y1.si.p);
        } else {
            l.Le = em.evalSurface(l.p, l.n, -l.wo);
            l.pdfLight = scene.emitterSelection.pmf(size_t(l.emitter)) * em.pdfDirect(y1.si.p, l.p, l.n, l.wo);
        }
        l.visible = unoccluded(scene, y1.si.endpoint(), {l.p, l.n, l.magnitude});
    }
    if (x1.scattered && y.vertices.size() > 1) {
        BaseVertex& y2 = y.vertices[1];
        y2.wi = normalize(y1.si.p - y2.si.p);
        if (y2.scattered) scatter(y2, y2.wo);
    }
    return y;
}

} // namespace

TEST_CASE("T-GR-2: a path's weights are the same from every pixel that can produce it", "[gradient]") {
    // For the balance weights over a set of pixels to sum to one over the techniques that can produce a path,
    // the shifts must compose: the weights computed from base path x in pixel k and from its shift y in pixel
    // m must agree, technique by technique. Diffuse scene: every shift reconnects at the primary hit.
    test::TempDir dir;
    for (const char* name : {"cornell-box", "delta-room", "plastic-room"}) {
        CAPTURE(name);
        const std::string file = std::string(name) == "delta-room"     ? deltaRoom(dir)
                                 : std::string(name) == "plastic-room" ? plasticRoom(dir)
                                                                       : test::shippedScene(name);
        const auto scene = loadScene(file);
        const Vec3 eye = scene->camera.position(); // a pinhole: its one lens point
        scene->camera = scene->camera.withResolution(48, 48);
        GradientSettings gs = settingsFor(*scene);
        gs.paths.maxDepth = 4;
        gs.paths.rrDepth = 10;
        // Pixels 9 apart: the primary hits lie far apart, so Jacobians are far from 1 and a missing one shows.
        const int size = 4, spacing = 9;
        Pcg32 rng(3, 5);
        int compared = 0, joinedLights = 0;
        for (int n = 0; n < 200; ++n) {
            const Vec2 corner(2 + rng.nextUInt() % 16, 2 + rng.nextUInt() % 16),
                offset(rng.nextDouble(), rng.nextDouble());
            auto pixel = [&](size_t j) {
                return corner + Vec2(double(spacing * (j % size)), double(spacing * (j / size))) + offset;
            };
            std::vector<std::optional<BaseVertex>> primary;
            for (size_t j = 0; j < size * size; ++j)
                primary.push_back(primaryVertex(*scene, pixel(j), eye));
            const size_t k = rng.nextUInt() % (size * size);
            IndependentSampler sampler(uint64_t(n), 9);
            const BasePath x = traceBasePath(*scene, gs.paths, gs.shiftThreshold, pixel(k), eye, primary[k], sampler);
            if (x.vertices.size() < 2 || !x.vertices[0].scattered) continue;
            // The weights of every technique j for every ending, seen from a base path in pixel `own`.
            auto weights = [&](const BasePath& base, size_t own) {
                std::vector<std::vector<EndingTerm>> terms(primary.size());
                for (size_t j = 0; j < primary.size(); ++j) {
                    if (j == own)
                        terms[j] = baseEndingTerms(*scene, base);
                    else
                        (void)shiftBasePath(*scene, base, primary[j], gs.shiftThreshold, terms[j], EarlyOut::Never);
                }
                std::vector<std::vector<double>> w(terms[own].size(), std::vector<double>(primary.size(), 0.0));
                for (size_t e = 0; e < w.size(); ++e) {
                    double sum = 0;
                    for (const auto& t : terms)
                        sum += t[e].density;
                    for (size_t j = 0; j < primary.size(); ++j)
                        w[e][j] = terms[j][e].density / sum;
                }
                return std::make_pair(w, terms);
            };
            const auto [wx, tx] = weights(x, k);
            for (size_t m = 0; m < primary.size(); ++m) {
                if (m == k || !primary[m]) continue;
                std::vector<EndingTerm> probe;
                const ShiftOutcome o = shiftBasePath(*scene, x, primary[m], gs.shiftThreshold, probe, EarlyOut::Never);
                // x_2 took a delta lobe (a smooth plastic's coat) but has a light sample: the shift's ending 2 is
                // y_1 -> x_2 -> light by the reconnection, and its path follows x's half vectors on, so a base
                // path of pixel m that ends at x_2 shifts back onto x's ending 2 (compared alone).
                const BaseVertex& x2 = x.vertices[1];
                const bool joinedLight = x.vertices[0].connectable && x2.connectable && x2.scattered && x2.delta() &&
                                         !probe[2].value.isBlack();
                if (!joinedLight && (o.cause != ShiftCause::Reconnected || o.reconnectDepth != 1)) continue;
                BasePath y = reconnectedPath(*scene, x, *primary[m]);
                if (joinedLight) {
                    y.vertices.resize(2);
                    y.vertices[1].scattered = false;
                    ++joinedLights;
                }
                // Only a path pixel m's path tracer could have traced is a base path there (a direction at the
                // edge of its lobe has a density that underflows).
                if (!(y.vertices[0].pdf > 1e-9) || y.vertices[0].fCos.isBlack() ||
                    (y.vertices[1].scattered && !(y.vertices[1].pdf > 1e-9)))
                    continue;
                const auto [wy, ty] = weights(y, m);
                for (size_t e = 0; e < (joinedLight ? 3 : wx.size()); ++e) {
                    // Where the path in pixel m carries light, its weights must agree: to the precision of a
                    // reconnection direction recomputed from float hit points (~1e-3, bsdf/bsdf.h), which moves
                    // densities near grazing by up to a percent.
                    if (ty[m][e].value.isBlack() || tx[m][e].value.isBlack()) continue;
                    ++compared;
                    for (size_t j = 0; j < primary.size(); ++j) {
                        CAPTURE(n, m, e, j);
                        CHECK(wy[e][j] == Approx(wx[e][j]).margin(2e-3).epsilon(2e-2));
                    }
                }
            }
        }
        CAPTURE(joinedLights);
        CHECK(compared > 100);
        if (std::string(name) == "plastic-room") CHECK(joinedLights > 20);
    }
}

TEST_CASE("the variance planes hold the sample variance of the passes' values", "[gradient]") {
    // Every pass gives every pixel one value of each plane; the film keeps the squares of the passes' values
    // (image/film.h). Snapshots after every pass give the same values independently (n mean_n - (n - 1)
    // mean_(n-1)), so the planes can be checked against the textbook sample variance of those values.
    test::TempDir dir;
    const auto scene = loadScene(deltaRoom(dir));
    scene->camera = scene->camera.withResolution(16, 16);
    const GradientSettings gs = settingsFor(*scene);
    GradientSettings tiled = gs;
    tiled.tile = 3;
    const GradientPathTracer gpt(*scene, gs);
    const PathReusing gdpr(*scene, tiled);
    for (const PixelEstimator* est : {static_cast<const PixelEstimator*>(&gpt), static_cast<const PixelEstimator*>(&gdpr)}) {
        CAPTURE(est == &gpt ? "G-PT" : "path reusing");
        const int passes = 6;
        SampleFilm film(scene->camera, est->planes());
        RenderSettings rs;
        rs.spp = passes;
        rs.snapshots = SnapshotSchedule::parseSamples("1,2,3,4,5,6");
        std::vector<file::Buffer> snaps;
        (void)render(*scene, *est, rs, film,
                     RunControl(2, [&](const RunProgress&, const file::Buffer& b) { snaps.push_back(b); }));
        REQUIRE(snaps.size() == size_t(passes));
        const file::Buffer last = film.toBuffer();
        auto channel = [](const file::Buffer& b, const std::string& name) -> const std::vector<float>& {
            const auto it = std::find(b.channels.begin(), b.channels.end(), name);
            REQUIRE(it != b.channels.end());
            return b.planes[size_t(it - b.channels.begin())];
        };
        int nonzero = 0;
        for (const char* plane : {"primal", "dx", "dy", "direct"}) {
            CAPTURE(plane);
            const std::vector<float>& var = channel(last, std::string(plane) + ".var");
            for (size_t i = 0; i < var.size(); ++i) {
                // Luminance of the pixel's sum after each pass, from the stored means and counts.
                std::vector<double> sums(1, 0.0);
                double scale = 0;
                for (const auto& b : snaps) {
                    const double n = b.sampleCounts[i];
                    REQUIRE(n == double(sums.size()));
                    double lum = 0, mag = 0;
                    for (int c = 0; c < 3; ++c) {
                        const double v = n * channel(b, std::string(plane) + "." + "RGB"[c])[i];
                        lum += v * Spectrum(c == 0, c == 1, c == 2).luminance();
                        mag += std::abs(v);
                    }
                    sums.push_back(lum);
                    scale = std::max(scale, mag);
                }
                double sumX = 0, sumX2 = 0;
                for (size_t p = 1; p < sums.size(); ++p) {
                    const double x = sums[p] - sums[p - 1];
                    sumX += x;
                    sumX2 += x * x;
                }
                const double n = passes, expected = (sumX2 - sumX * sumX / n) / (n - 1);
                CAPTURE(i, expected, var[i]);
                // The snapshots store float means: each pass's value is known to ~1e-7 of the sums.
                CHECK(std::abs(var[i] - expected) <= 1e-5 * (expected + scale * scale) + 1e-30);
                nonzero += var[i] > 0;
            }
        }
        CHECK(nonzero > 200);
    }
}

namespace {

// A path-space MLT run whose chain-state stream (lt-mutate --stream) is written to `file`, and the chains' own
// image; then the stream read back by the gradient stage (lt-gradient --from-paths). With a `target` (lt-mutate
// --target gradient) the chains, their seeds and b are that target's.
struct StreamedRun {
    std::vector<float> chainImage;
    double b = 0;
    file::Buffer gradients;
};
// `direct`: the direct split (sampling/direct_split.h): the chains without the paths of 1 and 2 edges, the gradient
// stage rendering them into the direct plane.
StreamedRun runStreamedChains(const Scene& scene, const std::string& file, uint64_t mutations, uint64_t seed,
                              const PathTarget& target = {}, DirectSplit direct = {-1}) {
    PathSettings bdpt;
    bdpt.maxDepth = scene.integrator.maxDepth;
    bdpt = direct.chainPaths(bdpt);
    const auto seeds = seedWithBdpt(scene, bdpt, 20000, 1024, seed * 7919 + 1, RunControl(2), target);
    std::vector<std::unique_ptr<Mutation>> owned;
    std::vector<WeightedMutation> mix;
    makeMutations(chooseMutations("bidirectional,lens", analyzeScene(scene)), {scene, bdpt.maxDepth, bdpt.minDepth}, {},
                  owned, mix);
    ChainRunSettings rs;
    rs.mutations = mutations;
    rs.chains = 32;
    rs.seed = seed;
    SampleFilm film(scene.camera);
    StreamedRun out;
    {
        file::Writer writer(file, file::FileKind::Paths, {{"producer", "test"}});
        PathDump dump;
        dump.writeRound = [&](const file::ChainRound& figures, std::vector<file::EncodedChainStates>&& states) {
            std::vector<const file::EncodedChainStates*> parts;
            for (const auto& s : states)
                parts.push_back(&s);
            writer.writeChainRound(figures, parts);
        };
        const auto st = runPathSpaceChains(scene, seeds, mix, rs, bdpt, 1.0 / 16, film, RunControl(2), dump, target);
        REQUIRE(st.health.nonFinite == 0);
        writer.finish();
        out.b = st.b;
        out.chainImage = film.develop(out.b);
    }
    file::Reader reader(file, file::FileKind::Paths);
    ShiftStatistics shifts;
    ChainStreamSettings settings;
    settings.direct = direct;
    settings.seed = seed;
    const auto gs = gradientsFromStream(scene, reader, settings, out.gradients, shifts, RunControl(2));
    REQUIRE(gs.health.nonFinite == 0);
    return out;
}

} // namespace

TEST_CASE("GDMLT: the chain-state stream credits every state as the chains' own image does", "[gradient][gdmlt]") {
    test::TempDir dir;
    const auto scene = loadScene(test::shippedScene("cornell-spheres"));
    scene->camera = scene->camera.withResolution(32, 32);
    const std::string file = (dir.path / "stream.ltp").string();
    const StreamedRun run = runStreamedChains(*scene, file, 32 * 32 * 16, 3);
    // The image the stream holds: (b / N) sum credit f / f* at each state's raster position.
    const file::Content content = file::readAll(file, file::FileKind::Paths);
    REQUIRE(!content.rounds.empty());
    SampleFilm film(scene->camera);
    uint64_t mutations = 0;
    for (const auto& round : content.rounds) {
        std::vector<Splat> splats;
        for (const auto& s : round.states)
            splats.push_back({Vec2(s.raster[0], s.raster[1]),
                              Spectrum(s.f[0], s.f[1], s.f[2]) * (s.credit / (double(s.target) * 32 * 32))});
        film.mergeSplats({&splats}, round.mutations - mutations);
        mutations = round.mutations;
    }
    CHECK(mutations == 32 * 32 * 16);
    CHECK(content.rounds.back().b == run.b);
    // Every mutation hands out a credit of one (a to the proposal, 1 - a to the state it was made from).
    double credit = 0;
    for (const auto& round : content.rounds)
        for (const auto& s : round.states)
            credit += s.credit;
    CHECK(credit == Approx(double(mutations)).epsilon(1e-9));

    // A damaged stream: a state off the film (NaN, or far away) is an error, never a splat.
    ChainGradientSplats splats;
    file::ChainState bad = content.rounds.back().states.back();
    for (const float x : {std::numeric_limits<float>::quiet_NaN(), 1e30f, -1.0f}) {
        bad.raster[0] = x;
        CHECK_THROWS_WITH(addChainState(*scene, cropWindow(scene->camera.film()), bad, 0.001, splats, nullptr),
                          Catch::Contains("off the film"));
    }
    CHECK(splats.primal.empty());
    const std::vector<float> image = film.develop(content.rounds.back().b);
    REQUIRE(image.size() == run.chainImage.size());
    // f, f* and the raster position are stored in binary32: relative errors of ~1e-7 in the values and
    // ~4e-6 pixels in the position, which moves the tent filter's weights by about as much.
    const float peak = *std::max_element(run.chainImage.begin(), run.chainImage.end());
    for (size_t i = 0; i < image.size(); ++i) {
        CAPTURE(i, image[i], run.chainImage[i]);
        CHECK(std::abs(image[i] - run.chainImage[i]) <= 1e-4f * std::abs(run.chainImage[i]) + 1e-6f * peak);
    }
}

TEST_CASE("GDMLT: primal and gradients from chain states are unbiased against BDPT, for both targets",
          "[gradient][gdmlt][long]") {
    test::TempDir dir;
    for (const auto& [name, target] :
         {std::pair{"cornell-box", "luminance"}, std::pair{"cornell-spheres", "luminance"},
          std::pair{"cornell-box", "gradient"}, std::pair{"cornell-spheres", "gradient"}}) {
        CAPTURE(name, target);
        const auto scene = loadScene(test::shippedScene(name));
        scene->camera = scene->camera.withResolution(32, 32);
        const PathTarget chainTarget =
            std::string(target) == "gradient" ? gradientTarget(*scene, 0.2, 0.001) : PathTarget{};
        const int runs = 16, w = 32, r = 8;
        // Per run: region means of the image (primal + direct), of its forward differences (dx and dy plus the
        // direct plane's differences) and of the L2 reconstruction, as T-GR-3.
        std::array<std::vector<std::vector<double>>, 4> chains;
        for (int run = 0; run < runs; ++run) {
            const StreamedRun s = runStreamedChains(*scene, (dir.path / "stream.ltp").string(), 32 * 32 * 64,
                                                    100 + uint64_t(run), chainTarget);
            const GradientImage g = gradientImageFromBuffer(s.gradients, "test");
            auto image = [&](int x, int y) { return at(g.primal, g.width, x, y) + at(*g.direct, g.width, x, y); };
            chains[0].push_back(regionMeans(w, w, r, image));
            chains[1].push_back(regionMeans(w - 1, w, r, [&](int x, int y) {
                return at(g.dx, g.width, x, y) + at(*g.direct, g.width, x + 1, y) - at(*g.direct, g.width, x, y);
            }));
            chains[2].push_back(regionMeans(w, w - 1, r, [&](int x, int y) {
                return at(g.dy, g.width, x, y) + at(*g.direct, g.width, x, y + 1) - at(*g.direct, g.width, x, y);
            }));
            ReconstructStatistics stats;
            const file::Buffer l2 = reconstructScreenedPoisson(g, ReconstructSettings{}, stats);
            chains[3].push_back(regionMeans(w, w, r, [&](int x, int y) {
                const size_t i = size_t(y * w + x);
                return Spectrum(l2.planes[0][i], l2.planes[1][i], l2.planes[2][i]);
            }));
        }
        std::array<std::vector<std::vector<double>>, 3> bdpt;
        for (int run = 0; run < runs; ++run) {
            const auto img = renderWith(test::PixelMethod::Bdpt, *scene, 16, 500 + uint64_t(run));
            auto px = [&](int x, int y) {
                const size_t i = size_t(y * w + x);
                return Spectrum(img[3 * i], img[3 * i + 1], img[3 * i + 2]);
            };
            bdpt[0].push_back(regionMeans(w, w, r, px));
            bdpt[1].push_back(regionMeans(w - 1, w, r, [&](int x, int y) { return px(x + 1, y) - px(x, y); }));
            bdpt[2].push_back(regionMeans(w, w - 1, r, [&](int x, int y) { return px(x, y + 1) - px(x, y); }));
        }
        for (int p = 0; p < 3; ++p) {
            CAPTURE(p);
            checkSameMeans(chains[size_t(p)], bdpt[size_t(p)]);
        }
        INFO("the L2 reconstruction");
        checkSameMeans(chains[3], bdpt[0]);
    }
}

TEST_CASE("GDMLT: in the furnace the gradient target's chains give zero gradients and the furnace's value",
          "[gradient][gdmlt][long]") {
    test::TempDir dir;
    const auto scene = loadScene(test::furnaceBox(dir, 0.5, 4));
    // Le * (1 + rho + rho^2 + rho^3), the directly seen emission in the direct plane; with the direct split the direct
    // plane holds the paths of 1 and 2 edges (1 + rho), rendered by the gradient stage, and the chains the rest.
    const double expected = 1 + 0.5 + 0.25 + 0.125;
    const PathTarget target = gradientTarget(*scene, 0.2, 0.001);
    const int directSamples = GENERATE(-1, 16);
    CAPTURE(directSamples);
    // Per independent run, the image means of primal + direct, dx and dy (a chain's pixels are correlated, so the
    // standard errors come from the runs), and with the split of the direct plane.
    std::array<std::vector<double>, 4> means;
    // 12 runs: each |mean - truth| / error is a Student t with 11 degrees of freedom, P(|t| > 5) about 4e-4.
    for (int run = 0; run < 12; ++run) {
        const StreamedRun s = runStreamedChains(*scene, (dir.path / "stream.ltp").string(), 24 * 24 * 32,
                                                40 + uint64_t(run), target, DirectSplit{directSamples});
        const GradientImage g = gradientImageFromBuffer(s.gradients, "test");
        double image = 0, dx = 0, dy = 0, direct = 0;
        for (int y = 0; y < int(g.height); ++y)
            for (int x = 0; x < int(g.width); ++x) {
                image += (at(g.primal, g.width, x, y) + at(*g.direct, g.width, x, y)).luminance();
                direct += at(*g.direct, g.width, x, y).luminance();
                if (x + 1 < int(g.width)) dx += at(g.dx, g.width, x, y).luminance();
                if (y + 1 < int(g.height)) dy += at(g.dy, g.width, x, y).luminance();
            }
        const double pixels = double(g.width) * double(g.height);
        means[0].push_back(image / pixels);
        means[1].push_back(dx / (pixels - g.height));
        means[2].push_back(dy / (pixels - g.width));
        means[3].push_back(direct / pixels);
    }
    const double truth[4] = {expected, 0, 0, directSamples > 0 ? 1.5 : 1.0};
    for (int p = 0; p < 4; ++p) {
        const auto m = test::meanAndError(means[size_t(p)]);
        CAPTURE(p, m.mean, m.error);
        CHECK(std::abs(m.mean - truth[p]) <= 5 * m.error + 1e-12);
    }
}
