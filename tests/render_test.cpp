// The pixel estimators (BDPT with MIS, each BDPT strategy alone, the path tracer) against scenes with
// analytic answers. Tolerances come from the spread of the pixel estimates (each pixel is an independent
// estimate of the same value in these scenes), never from observed values.
#include <catch2/catch.hpp>

#include <cmath>

#include "image/film.h"
#include "math/constants.h"
#include "math/rng.h"
#include "reconstruct/gradient_image.h"
#include "sampling/render.h"
#include "scene/emitters/preetham_sun.h"
#include "scene/emitters/sun_sky.h"
#include "scene/scene.h"
#include "test_util.h"

using namespace lt;

namespace {

struct PixelStats {
    double mean = 0, stderr_ = 0;
    size_t n = 0;
};

// Mean and standard error of one channel over the pixels in [x0, x1) x [y0, y1) of the crop window.
PixelStats stats(const std::vector<float>& img, int width, int x0, int y0, int x1, int y1, int c = 1) {
    PixelStats s;
    double sum = 0, sum2 = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            const double v = img[3 * (size_t(y) * size_t(width) + size_t(x)) + size_t(c)];
            sum += v;
            sum2 += v * v;
            ++s.n;
        }
    s.mean = sum / double(s.n);
    const double var = std::max(0.0, sum2 / double(s.n) - s.mean * s.mean) * double(s.n) / double(s.n - 1);
    s.stderr_ = std::sqrt(var / double(s.n));
    return s;
}

std::vector<float> renderImage(const Scene& scene, test::PixelMethod method, int spp, PathSettings b, uint64_t seed = 1,
                               int threads = 2, SamplerKind sampler = SamplerKind::Independent) {
    SampleFilm film(scene.camera);
    RenderSettings rs;
    rs.paths = b;
    rs.spp = spp;
    rs.seed = seed;
    rs.sampler = sampler;
    const RenderStats st = render(scene, *test::makePixelEstimator(method, scene, b), rs, film, RunControl(threads));
    REQUIRE(st.health.nonFinite == 0);
    return film.develop();
}

// Both pixel estimators on a scene of paths of at most two edges whose every pixel has the value `expected`
// (a plane under one light): the image mean within 5 standard errors of the pixels, plus a known `bias`.
void checkTwoEdgeImage(const Scene& scene, int size, int spp, double expected, double bias = 0) {
    for (test::PixelMethod m : {test::PixelMethod::Bdpt, test::PixelMethod::PathTracing}) {
        CAPTURE(int(m));
        PathSettings b;
        b.maxDepth = 2;
        const auto img = renderImage(scene, m, spp, b);
        const PixelStats s = stats(img, size, 0, 0, size, size);
        INFO("mean " << s.mean << " +- " << s.stderr_ << ", expected " << expected);
        CHECK(std::abs(s.mean - expected) <= 5 * s.stderr_ + bias + 1e-6 * expected);
    }
}

} // namespace

TEST_CASE("furnace box: every pixel is Le * sum of rho^k for k < maxDepth", "[render]") {
    test::TempDir dir;
    const double rho = 0.5;
    for (int depth : {1, 3, 6}) {
        CAPTURE(depth);
        const auto scene = loadScene(test::furnaceBox(dir, rho, depth));
        double expected = 0;
        for (int k = 0; k < depth; ++k) expected += std::pow(rho, k);
        PathSettings b;
        b.maxDepth = depth;
        for (test::PixelMethod m : {test::PixelMethod::Bdpt, test::PixelMethod::PathTracing})
            for (SamplerKind sampler : {SamplerKind::Independent, SamplerKind::Sobol}) {
                CAPTURE(int(m), int(sampler));
                // Each pixel is an independent estimate under either sampler (the Sobol sampler's scrambles
                // are seeded per pixel), so the pixels' spread gives the standard error.
                const auto img = renderImage(*scene, m, 16, b, 1, 2, sampler);
                const PixelStats s = stats(img, 24, 0, 0, 24, 24);
                // 5 standard errors: a false failure has probability below 1e-6 per check.
                // Plus the float32 rounding of the film's output (2^-24 relative, a few roundings).
                CHECK(std::abs(s.mean - expected) < 5 * s.stderr_ + 1e-6 * expected);
            }
    }
}

TEST_CASE("furnace box: border pixels with wide filters at small scene scale", "[render]") {
    // Camera samples of border pixels land outside the crop window with tent and gaussian filters;
    // light tracing must reach them too, or the MIS weights there sum to less than one (a loss that grows
    // as the scene shrinks, since the t = 1 density ratio carries units of 1/length^2).
    test::TempDir dir;
    for (const std::string filter : {"tent", "gaussian"}) {
        CAPTURE(filter);
        const auto scene = loadScene(test::furnaceBox(dir, 0.5, 3, filter, 0.01));
        PathSettings b;
        b.maxDepth = 3;
        const auto img = renderImage(*scene, test::PixelMethod::Bdpt, 32, b);
        std::vector<float> border;
        for (int y = 0; y < 24; ++y)
            for (int x = 0; x < 24; ++x)
                if (x == 0 || y == 0 || x == 23 || y == 23)
                    for (int c = 0; c < 3; ++c) border.push_back(img[3 * size_t(y * 24 + x) + size_t(c)]);
        const PixelStats s = stats(border, int(border.size() / 3), 0, 0, int(border.size() / 3), 1);
        CHECK(std::abs(s.mean - 1.75) < 5 * s.stderr_ + 1e-6);
    }
}

TEST_CASE("furnace box: each BDPT strategy alone is unbiased for its path length", "[render]") {
    test::TempDir dir;
    const double rho = 0.6;
    const int depth = 3;
    const auto scene = loadScene(test::furnaceBox(dir, rho, depth));
    // Paths of exactly k edges carry Le rho^(k-1); a strategy (s, t) samples paths of s + t - 1 edges.
    for (int s = 0; s <= 3; ++s)
        for (int t = 1; t <= 4; ++t) {
            const int edges = s + t - 1;
            if (edges < 1 || edges > depth || (s == 1 && t == 1)) continue;
            CAPTURE(s, t);
            PathSettings b;
            b.maxDepth = depth;
            b.onlyS = s;
            b.onlyT = t;
            const auto img = renderImage(*scene, test::PixelMethod::Bdpt, 32, b);
            const PixelStats st = stats(img, 24, 0, 0, 24, 24);
            const double expected = std::pow(rho, edges - 1);
            CHECK(std::abs(st.mean - expected) < 5 * st.stderr_ + 1e-6 * expected);
        }
}

TEST_CASE("a convex diffuse sphere under a uniform environment has radiance albedo * L", "[render]") {
    test::TempDir dir;
    const auto scene = loadScene(test::skySphere(dir));
    for (test::PixelMethod m : {test::PixelMethod::Bdpt, test::PixelMethod::PathTracing}) {
        CAPTURE(int(m));
        const auto img = renderImage(*scene, m, 16, PathSettings{});
        const PixelStats s = stats(img, 32, 12, 12, 20, 20);
        CHECK(std::abs(s.mean - 1.4) < 5 * s.stderr_ + 1e-6);
        // The corners see the sky.
        const PixelStats c = stats(img, 32, 0, 0, 3, 3);
        CHECK(c.mean == Approx(2.0).epsilon(1e-6));
    }
}

TEST_CASE("a cut-out (mask) lets 1 - opacity of the sky through", "[render]") {
    // A black plane masked to opacity 0.3 fills the view in front of a sky of radiance 2: each camera path
    // passes the mask with probability 0.7 (seeing 2) or stops on the black surface, so a pixel's value is
    // 2 x Bernoulli(0.7) per sample: mean 1.4. The tolerance is the mean's standard error (5 sigma).
    test::TempDir dir;
    const auto scene = loadScene(dir.write("mask.xml", R"(<scene version="0.6.0">
<sensor type="perspective"><float name="fov" value="30"/><film type="hdrfilm"><integer name="width" value="16"/>
<integer name="height" value="16"/></film></sensor>
<shape type="rectangle"><transform name="toWorld"><scale value="100"/><translate z="5"/></transform>
  <bsdf type="mask"><float name="opacity" value="0.3"/>
    <bsdf type="twosided"><bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf></bsdf></bsdf></shape>
<emitter type="constant"><rgb name="radiance" value="2"/></emitter>
</scene>)"));
    for (test::PixelMethod m : {test::PixelMethod::Bdpt, test::PixelMethod::PathTracing}) {
        CAPTURE(int(m));
        const int spp = 16;
        const auto img = renderImage(*scene, m, spp, PathSettings{});
        const PixelStats st = stats(img, 16, 0, 0, 16, 16);
        const double n = 16.0 * 16.0 * spp;
        const double sigma = 2 * std::sqrt(0.3 * 0.7 / n);
        CHECK(std::abs(st.mean - 1.4) < 5 * sigma);
    }
}

TEST_CASE("rendering is bit-identical whatever the thread count", "[render]") {
    test::TempDir dir;
    const auto scene = loadScene(test::furnaceBox(dir, 0.5, 4));
    PathSettings b;
    b.maxDepth = 4;
    for (SamplerKind sampler : {SamplerKind::Independent, SamplerKind::Sobol}) {
        CAPTURE(int(sampler));
        const auto one = renderImage(*scene, test::PixelMethod::Bdpt, 4, b, 7, 1, sampler);
        const auto two = renderImage(*scene, test::PixelMethod::Bdpt, 4, b, 7, 2, sampler);
        CHECK(one == two);
    }
}

TEST_CASE("a diffuse plane under a point light: L = rho/pi I cos / d^2", "[render]") {
    test::TempDir dir;
    // Camera 4 above the plane looking straight down; point light 2 above the plane, off center.
    const double rho = 0.6, I = 5, h = 2;
    const Vec3 light{0.3, h, -0.2};
    const auto scene = loadScene(dir.write("plane.xml", R"(<scene version="0.5.0">
  <integrator type="path"><integer name="maxDepth" value="2"/></integrator>
  <sensor type="perspective"><float name="fov" value="50"/>
    <transform name="toWorld"><lookat origin="0,4,0" target="0,0,0" up="0,0,-1"/></transform>
    <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="24"/><rfilter type="box"/></film>
  </sensor>
  <emitter type="point"><point name="position" x="0.3" y="2" z="-0.2"/><rgb name="intensity" value="5"/></emitter>
  <shape type="rectangle"><transform name="toWorld"><scale value="10"/><rotate x="1" angle="-90"/></transform>
    <bsdf type="diffuse"><rgb name="reflectance" value="0.6"/></bsdf></shape>
</scene>)"));
    // Expected pixel values: the box-filtered radiance, integrated over each pixel by a 16 x 16 grid
    // of rays (the radiance is smooth: the grid error is far below the Monte Carlo noise).
    std::vector<double> expected(24 * 24);
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 24; ++x) {
            double sum = 0;
            for (int j = 0; j < 16; ++j)
                for (int i = 0; i < 16; ++i) {
                    const Ray r =
                        scene->camera.generateRay({x + (i + 0.5) / 16, y + (j + 0.5) / 16}, scene->camera.position());
                    const Vec3 p = r.o + r.d * (-r.o.y / r.d.y);
                    const Vec3 toLight = light - p;
                    const double d2 = lengthSquared(toLight);
                    sum += rho / Pi * I * (toLight.y / std::sqrt(d2)) / d2;
                }
            expected[size_t(y * 24 + x)] = sum / 256;
        }
    for (test::PixelMethod m : {test::PixelMethod::Bdpt, test::PixelMethod::PathTracing}) {
        CAPTURE(int(m));
        PathSettings b;
        b.maxDepth = 2;
        const auto img = renderImage(*scene, m, 8, b);
        // Residuals of independent pixels: their mean is 0 within its standard error.
        std::vector<float> residual(img.size());
        for (size_t i = 0; i < expected.size(); ++i)
            for (size_t c = 0; c < 3; ++c) residual[3 * i + c] = float(img[3 * i + c] - expected[i]);
        const PixelStats r = stats(residual, 24, 0, 0, 24, 24);
        CHECK(std::abs(r.mean) < 5 * r.stderr_ + 1e-6);
        // And the image is not trivially close: the expected values span a range.
        CHECK(*std::max_element(expected.begin(), expected.end()) > 2 * *std::min_element(expected.begin(), expected.end()));
    }
}

TEST_CASE("a diffuse plane in sunlight: L = rho/pi E cos, for the sun disk in a map and as a directional light",
          "[render][daylight]") {
    test::TempDir dir;
    // The sun 40 degrees from the zenith, turbidity 3; a plane of albedo 0.5 seen from above.
    const double rho = 0.5, zenith = degToRad(40);
    const Spectrum E = preethamSunRadiance(zenith, 3) * (TwoPi * (1 - std::cos(SunAngularRadius)));
    for (const char* radiusScale : {"1", "0"}) {
        CAPTURE(radiusScale);
        const auto scene = loadScene(dir.write("sun.xml", std::string(R"(<scene version="0.6.0">
  <sensor type="perspective"><float name="fov" value="30"/>
    <transform name="toWorld"><lookat origin="0,4,0" target="0,0,0" up="0,0,-1"/></transform>
    <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/><rfilter type="box"/></film>
  </sensor>
  <emitter type="sun"><vector name="sunDirection" x="0" y=")") +
                                                              std::to_string(std::cos(zenith)) + R"(" z=")" +
                                                              std::to_string(std::sin(zenith)) + R"("/>
    <integer name="resolution" value="2048"/><float name="sunRadiusScale" value=")" +
                                                              radiusScale + R"("/></emitter>
  <shape type="rectangle"><transform name="toWorld"><scale value="10"/><rotate x="1" angle="-90"/></transform>
    <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf></shape>
</scene>)"));
        const double expected = rho / Pi * E.g * std::cos(zenith);
        // The map moves the disk's light to the centres of the texels it covers: at most a texel
        // (2 pi / 2048) away, which changes cos(zenith) by at most sin(zenith) times that.
        const double texelBias = std::string(radiusScale) == "1" ? rho / Pi * E.g * std::sin(zenith) * TwoPi / 2048 : 0;
        checkTwoEdgeImage(*scene, 16, 8, expected, texelBias);
    }
}

TEST_CASE("a thin lens blurs an edge out of focus by its circle of confusion and keeps it sharp in focus",
          "[render][thinlens]") {
    test::TempDir dir;
    // Two diffuse half-planes at distance 4 across the view axis, albedo 0.8 (x < 0) and 0.2 (x > 0), under
    // a uniform sky of radiance 1: each sends its albedo. A lens of radius 0.2 focused at distance 2 spreads
    // a point of the focus plane over a disk of radius 0.2 (4 - 2) / 2 = 0.2 on the half-planes, 3 pixels.
    const double D = 4, R = 0.2;
    auto scene = [&](double focus) {
        return loadScene(dir.write("lens.xml", R"(<scene version="0.6.0">
  <sensor type="thinlens"><float name="fov" value="30"/><float name="apertureRadius" value=")" +
                                                   std::to_string(R) + R"("/><float name="focusDistance" value=")" +
                                                   std::to_string(focus) +
                                                   R"("/>
    <transform name="toWorld"><lookat origin="0,0,0" target="0,0,1" up="0,1,0"/></transform>
    <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="8"/><rfilter type="box"/></film>
  </sensor>
  <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
  <shape type="rectangle"><transform name="toWorld"><scale value="10"/><rotate y="1" angle="180"/><translate x="-10" z="4"/></transform>
    <bsdf type="diffuse"><rgb name="reflectance" value="0.8"/></bsdf></shape>
  <shape type="rectangle"><transform name="toWorld"><scale value="10"/><rotate y="1" angle="180"/><translate x="10" z="4"/></transform>
    <bsdf type="diffuse"><rgb name="reflectance" value="0.2"/></bsdf></shape>
</scene>)"));
    };
    for (const double focus : {2.0, D}) {
        CAPTURE(focus);
        const auto s = scene(focus);
        REQUIRE(s->camera.hasAperture());
        // Expected columns, independently of the thin-lens code: the pinhole ray of a raster position meets
        // the focus plane at p; the ray from a lens point l through p reaches the half-planes at x(l).
        // Averaged over the pixel (8 x 8 raster points) and the lens (a polar grid of equal areas).
        const PerspectiveCamera pinhole = PerspectiveCamera(Transform(), 30, FovAxis::X, s->camera.film(), 0.01);
        std::vector<double> column(32);
        for (int x = 0; x < 32; ++x) {
            double sum = 0;
            int count = 0;
            for (int i = 0; i < 8; ++i)
                for (int j = 0; j < 8; ++j) {
                    const Ray r = pinhole.generateRay({x + (i + 0.5) / 8, 4 + (j + 0.5) / 8}, pinhole.position());
                    const Vec3 p = r.d * (focus / r.d.z);
                    for (int a = 0; a < 16; ++a)
                        for (int b = 0; b < 32; ++b) {
                            const double rho = R * std::sqrt((a + 0.5) / 16), phi = TwoPi * (b + 0.5) / 32;
                            const Vec3 l(rho * std::cos(phi), rho * std::sin(phi), 0);
                            const Vec3 hit = l + (p - l) * (D / focus);
                            sum += hit.x < 0 ? 0.8 : 0.2;
                            ++count;
                        }
                }
            column[size_t(x)] = sum / count;
        }
        // The edge is sharp in focus (no column between 0.8 and 0.2) and spread out of it over the blur disk's
        // diameter, 2 x 0.2 on the half-planes, whose pixels are 2 x 4 tan(15 deg) / 32 = 0.067 wide: 6 columns.
        int between = 0;
        for (double c : column)
            between += c > 0.21 && c < 0.79;
        CHECK(between == (focus == D ? 0 : 6));
        for (test::PixelMethod m : {test::PixelMethod::Bdpt, test::PixelMethod::PathTracing}) {
            CAPTURE(int(m));
            PathSettings b;
            b.maxDepth = 2;
            const auto img = renderImage(*s, m, 64, b);
            // Residuals of independent pixels, by bands of columns: left of the blur, its two halves, right of it.
            for (const auto& [x0, x1] : {std::pair{0, 10}, std::pair{10, 16}, std::pair{16, 22}, std::pair{22, 32}}) {
                std::vector<float> residual(img.size());
                for (int y = 0; y < 8; ++y)
                    for (int x = 0; x < 32; ++x)
                        for (int c = 0; c < 3; ++c) {
                            const size_t i = 3 * (size_t(y) * 32 + size_t(x)) + size_t(c);
                            residual[i] = float(img[i] - column[size_t(x)]);
                        }
                const PixelStats r = stats(residual, 32, x0, 0, x1, 8);
                INFO("columns " << x0 << "-" << x1 << ": residual " << r.mean << " +- " << r.stderr_);
                CHECK(std::abs(r.mean) < 5 * r.stderr_ + 1e-6);
            }
        }
    }
}

TEST_CASE("a bump map tilts the shading normal: a diffuse plane under a directional light by Blinn's frame",
          "[render][bumpmap]") {
    test::TempDir dir;
    // Displacement: a 2 x 1 grey image 0 | 1, clamped, read bilinearly: between the texel centres (u in [0.25,
    // 0.75]) it rises by 2 per unit u; scaled by 0.5, by 1. The rectangle [-1, 1]^2 (uv = [0, 1]^2, |dp/du| =
    // 2) displaced that way has tangent dp/du + n and normal (-1, 0, 2) / sqrt(5) there (Blinn 1978;
    // Mitsuba's bumpmap), 26.6 degrees from +z toward -x.
    test::writeRgbExr(dir.file("ramp.exr"), 2, 1, {0, 0, 0, 1, 1, 1});
    const Vec3 toLight = normalize(Vec3(0.6, 0, 1));
    auto scene = [&](bool bumped) {
        const std::string diffuse = R"(<bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf>)";
        const std::string bsdf = bumped
                                     ? R"(<bsdf type="bumpmap"><texture type="scale"><float name="scale" value="0.5"/>
      <texture type="bitmap"><string name="filename" value="ramp.exr"/><string name="wrapMode" value="clamp"/>
        <float name="gamma" value="1"/></texture></texture>)" +
                                           diffuse + "</bsdf>"
                                     : diffuse;
        return loadScene(dir.write("bump.xml", R"(<scene version="0.6.0">
  <sensor type="perspective"><float name="fov" value="10"/>
    <transform name="toWorld"><lookat origin="0,0,4" target="0,0,0" up="0,1,0"/></transform>
    <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/><rfilter type="box"/></film>
  </sensor>
  <emitter type="directional"><vector name="direction" x="-0.6" y="0" z="-1"/><rgb name="irradiance" value="1"/></emitter>
  <shape type="rectangle">)" + bsdf + R"(</shape>
</scene>)"),
                         {}, UnknownProperties::Fail);
    };
    const auto flat = scene(false), bumped = scene(true);
    CHECK(bumped->bsdfs.at(0).bsdf->typeName() == "bumpmap");
    // The frame itself, at a point of the ramp, from the unbumped geometry and the slope alone.
    const SurfaceInteraction plain = flat->shapes[0].surfaceAt(0, {0.2, 0.3});
    const SurfaceInteraction tilted = bumped->shapes[0].surfaceAt(0, {0.2, 0.3});
    REQUIRE(plain.uv.x > 0.3);
    REQUIRE(plain.uv.x < 0.7);
    const double slope = 1.0; // displacement per unit u
    const Vec3 expectedNormal = normalize(cross(plain.dpdu + plain.shading.n * slope, plain.dpdv)) *
                                (dot(cross(plain.dpdu, plain.dpdv), plain.ng) > 0 ? 1.0 : -1.0);
    CHECK(length(tilted.shading.n - expectedNormal) < 1e-6);
    CHECK(length(tilted.shading.n - normalize(Vec3(-1, 0, 2))) < 1e-6);
    CHECK(tilted.ng == plain.ng);
    // The image: L = rho / pi E cos(light, n') (the shading-normal BSDF, geometric cosines in G), exact for
    // next-event estimation of a directional light: no noise to speak of.
    const double expected = 0.5 / Pi * dot(toLight, normalize(Vec3(-1, 0, 2)));
    CHECK(std::abs(expected - 0.5 / Pi * toLight.z) > 0.03); // the flat plane's value is far off
    checkTwoEdgeImage(*bumped, 8, 4, expected);
}

TEST_CASE("BDPT and path tracing agree on the public cornell-box", "[render]") {
    const auto scene = loadScene(test::shippedScene("cornell-box"));
    scene->camera = scene->camera.withResolution(36, 36);
    const int runs = 6;
    // Mean luminance of each of the 3 x 3 regions of the image, per independent run (seed).
    auto regions = [&](test::PixelMethod m, uint64_t seed) {
        PathSettings b;
        b.maxDepth = scene->integrator.maxDepth;
        const auto img = renderImage(*scene, m, 8, b, seed);
        std::vector<double> out(9, 0.0);
        for (int y = 0; y < 36; ++y)
            for (int x = 0; x < 36; ++x) {
                const size_t i = size_t(y * 36 + x);
                out[size_t((y / 12) * 3 + x / 12)] +=
                    Spectrum(img[3 * i], img[3 * i + 1], img[3 * i + 2]).luminance() / 144.0;
            }
        return out;
    };
    std::vector<std::vector<double>> bd, pt;
    for (int r = 0; r < runs; ++r) {
        bd.push_back(regions(test::PixelMethod::Bdpt, 100 + uint64_t(r)));
        pt.push_back(regions(test::PixelMethod::PathTracing, 200 + uint64_t(r)));
    }
    for (size_t k = 0; k < 9; ++k) {
        CAPTURE(k);
        auto meanVar = [&](const std::vector<std::vector<double>>& v, double& mean, double& var) {
            mean = 0;
            for (const auto& x : v) mean += x[k] / runs;
            var = 0;
            for (const auto& x : v) var += (x[k] - mean) * (x[k] - mean) / (runs - 1);
        };
        double mb, vb, mp, vp;
        meanVar(bd, mb, vb);
        meanVar(pt, mp, vp);
        // Welch's t with the spread of independent runs; 5 standard errors (about 10 degrees of freedom:
        // a false failure has probability ~5e-4 per region).
        const double se = std::sqrt(vb / runs + vp / runs);
        CHECK(std::abs(mb - mp) < 5 * se);
        CHECK(mb > 0.01);
    }
}

TEST_CASE("the film merges splat lists in parallel bands exactly as one after another", "[render]") {
    // SampleFilm::mergeSplats (the Markov chains' rounds) must give the image of merge() list by list, bit
    // for bit: each pixel adds its splats in the same order. A gaussian filter (radius 2) with a crop window
    // whose rows are not a multiple of the 16-row bands; splats on band boundaries, on the crop's edges
    // and outside it.
    Film f;
    f.width = 61;
    f.height = 53;
    f.cropX = 3;
    f.cropY = 5;
    f.cropWidth = 50;
    f.cropHeight = 37;
    f.filter.type = PixelFilter::Type::Gaussian;
    f.filter.radius = 2;
    const PerspectiveCamera camera(Transform(), 45, FovAxis::X, f, 0.01);
    Pcg32 rng(3, 4);
    std::vector<std::vector<Splat>> lists(7);
    for (auto& list : lists)
        for (int i = 0; i < 400; ++i) {
            const double y = i % 5 == 0 ? f.cropY + 16 * (i % 3) + 0.5 * (i % 2) : f.cropY - 4 + rng.nextDouble() * 46;
            list.push_back({Vec2(f.cropX - 4 + rng.nextDouble() * 59, y),
                            Spectrum(rng.nextDouble(), rng.nextDouble() * 1e3, rng.nextDouble() * 1e-3)});
        }
    SampleFilm serial(camera), banded(camera);
    std::vector<const std::vector<Splat>*> pointers;
    for (const auto& list : lists) {
        TileResult t;
        t.splats = list;
        t.lightPaths = 10;
        serial.merge(t);
        pointers.push_back(&list);
    }
    banded.mergeSplats(pointers, 70);
    CHECK(serial.lightPaths() == banded.lightPaths());
    const auto a = serial.develop(), b = banded.develop();
    REQUIRE(a.size() == b.size());
    size_t differ = 0, nonzero = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        differ += a[i] != b[i];
        nonzero += a[i] != 0;
    }
    CHECK(differ == 0);
    CHECK(nonzero > a.size() / 2);
}

namespace {
// A pixel estimator with further planes, as a gradient-domain one will be: the image I(x, y) = x + 2 y
// (exact in every sample), and its forward differences by the symmetric estimator, each sample at p
// giving half of dx(p) = I(p + (1,0)) - I(p) and half of dx(p - (1,0)) = I(p) - I(p - (1,0)) (and dy alike).
class RampEstimator final : public PixelEstimator {
public:
    Spectrum estimate(const Vec2&, SampleGenerator&, PixelSample& out) const override {
        const double x = out.x, y = out.y;
        out.planes.push_back({0, 0, 0, Spectrum(0.5 * 1)});
        out.planes.push_back({0, -1, 0, Spectrum(0.5 * 1)});
        out.planes.push_back({1, 0, 0, Spectrum(0.5 * 2)});
        out.planes.push_back({1, 0, -1, Spectrum(0.5 * 2)});
        return Spectrum(x + 2 * y);
    }
    bool tracesLightPaths() const override { return false; }
    std::vector<std::string> planes() const override { return {"dx", "dy"}; }
};
} // namespace

TEST_CASE("the render loop fills a pixel estimator's further planes, and the film's buffer reads as a "
          "gradient-domain input",
          "[render]") {
    auto scene = loadScene(test::shippedScene("cornell-box"));
    scene->camera = scene->camera.withResolution(8, 6);
    const RampEstimator ramp;
    RenderSettings rs;
    rs.spp = 3;
    rs.tileSize = 4; // a neighbour's values land in another tile
    SampleFilm plain(scene->camera);
    CHECK(test::errorOf([&] { (void)render(*scene, ramp, rs, plain, {}); }).find("planes") != std::string::npos);

    SampleFilm film(scene->camera, ramp.planes());
    (void)render(*scene, ramp, rs, film, {});
    const file::Buffer b = film.toBuffer();
    CHECK(b.channels ==
          std::vector<std::string>{"primal.R", "primal.G", "primal.B", "dx.R", "dx.G", "dx.B", "dy.R", "dy.G", "dy.B",
                                   "primal.var", "dx.var", "dy.var"});
    // Every pass gives every pixel the same values: no variance.
    for (size_t c = 9; c < 12; ++c)
        for (const float v : b.planes[c])
            CHECK(v == Approx(0).margin(1e-9));
    const GradientImage g = gradientImageFromBuffer(b, "ramp");
    for (uint32_t y = 0; y < 6; ++y)
        for (uint32_t x = 0; x < 8; ++x) {
            const size_t i = y * 8 + x;
            CHECK(g.primal[1][i] == Approx(x + 2.0 * y));
            // The last column of dx and last row of dy leave the image: only their own half arrives.
            CHECK(g.dx[1][i] == Approx(x + 1 < 8 ? 1.0 : 0.5));
            CHECK(g.dy[1][i] == Approx(y + 1 < 6 ? 2.0 : 1.0));
        }
}
