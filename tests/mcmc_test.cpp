// The Markov-chain machinery: the primary-sample vector, the Metropolis-Hastings step with expected-value
// accumulation, and the primary-space chains against analytic answers and against BDPT. Tolerances come
// from the spread of independent chains (or runs), never from an observed value.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <optional>

#include "manifold/chains_in_path.h"
#include "math/constants.h"
#include "util/error.h"
#include "mcmc/metropolis.h"
#include "mcmc/mutations/bidirectional_mutation.h"
#include "mcmc/mutations/caustic_perturbation.h"
#include "mcmc/mutations/lens_perturbation.h"
#include "mcmc/mutations/lens_subpath_mutation.h"
#include "mcmc/mutations/multi_chain_perturbation.h"
#include "mcmc/path_space_chains.h"
#include "mcmc/primary_sample_vector.h"
#include "mcmc/primary_space_chains.h"
#include "mcmc/mutation_selection.h"
#include "path/path_record.h"
#include "path/scatter.h"
#include "sampling/render.h"
#include "chain_runs.h"
#include "test_util.h"

using namespace lt;
using namespace lt::test;

namespace {
// The chain state of seed record i, or nothing when it does not fit the scene (seed runs keep a few
// records that no longer carry light once re-created; the tests skip them).
std::optional<MarkovPath> stateOf(const Scene& scene, const file::PathRecord& record, size_t i) {
    try {
        return pathFromRecord(scene, record, i);
    } catch (const Error&) {
        return std::nullopt;
    }
}
} // namespace

TEST_CASE("primary sample vector: rejection restores, streams are independent, large steps are fresh", "[mcmc]") {
    PrimarySampleVector u(Pcg32(1, 1), Pcg32(2, 2));
    // Initial state: 3 camera numbers, 2 light numbers.
    u.startStream(SampleGenerator::CameraStream);
    std::vector<double> cam = {u.next1D(), u.next1D(), u.next1D()};
    u.startStream(SampleGenerator::LightStream);
    std::vector<double> light = {u.next1D(), u.next1D()};
    for (double x : cam)
        CHECK((x >= 0 && x < 1));

    // A small step moves every read coordinate a little (at most s2 on the torus) ...
    u.startIteration(false);
    u.startStream(SampleGenerator::CameraStream);
    for (int i = 0; i < 3; ++i) {
        const double v = u.next1D();
        const double d = std::abs(v - cam[size_t(i)]);
        CHECK(std::min(d, 1 - d) <= SmallStepKernel{}.s2() + 1e-15);
        CHECK(std::min(d, 1 - d) >= SmallStepKernel{}.s1() - 1e-15);
    }
    // ... reading more camera numbers than before does not shift the light stream ...
    (void)u.next1D();
    u.startStream(SampleGenerator::LightStream);
    const double l0 = u.next1D();
    const double d = std::abs(l0 - light[0]);
    CHECK(std::min(d, 1 - d) <= SmallStepKernel{}.s2() + 1e-15);
    // ... and rejection restores exactly what the proposal changed.
    u.reject();
    for (int i = 0; i < 3; ++i)
        CHECK(u.value(SampleGenerator::CameraStream, size_t(i)) == cam[size_t(i)]);
    CHECK(u.value(SampleGenerator::LightStream, 0) == light[0]);
    CHECK(u.value(SampleGenerator::LightStream, 1) == light[1]);

    // An accepted large step: every coordinate read is new, and stays after acceptance.
    u.startIteration(true);
    u.startStream(SampleGenerator::CameraStream);
    const double fresh = u.next1D();
    u.accept();
    CHECK(u.value(SampleGenerator::CameraStream, 0) == fresh);
}

TEST_CASE("Kelemen's small step is symmetric and bounded", "[mcmc]") {
    const SmallStepKernel k;
    Pcg32 rng(5, 5);
    // Offsets from 0.5 (no wrap): mean zero within 5 standard errors; |offset| in [s1, s2]; the log of
    // |offset| is uniform on [ln s1, ln s2] (density 1 / (r ln(s2/s1))), so its mean is the midpoint.
    const int n = 200000;
    double sum = 0, sum2 = 0, logSum = 0;
    for (int i = 0; i < n; ++i) {
        const double o = k.mutate(0.5, rng) - 0.5;
        REQUIRE(std::abs(o) >= k.s1() * (1 - 1e-12));
        REQUIRE(std::abs(o) <= k.s2() * (1 + 1e-12));
        sum += o;
        sum2 += o * o;
        logSum += std::log(std::abs(o));
    }
    const double se = std::sqrt(sum2 / n / n);
    CHECK(std::abs(sum / n) < 5 * se);
    const double logRange = std::log(k.s2() / k.s1());
    const double logSe = logRange / std::sqrt(12.0 * n); // standard error of the mean of a uniform
    CHECK(std::abs(logSum / n - 0.5 * (std::log(k.s1()) + std::log(k.s2()))) < 5 * logSe);
}

TEST_CASE("stationarity on a tiny primary space whose dimension changes with the state", "[mcmc]") {
    // Stationarity (as in mcmc_stationarity_test.cpp) with a target whose second coordinate is read only
    // on half the space: f(u) = 3 u1^2 where u0 < 1/2 (u1 read), and 1 elsewhere (u1 not read). The chain
    // must visit u0 < 1/2 half of the time and, there, u1 with density 3 u1^2: this needs the missed small
    // steps and large steps of the unread coordinate (mcmc/primary_sample_vector.h).
    const int chains = 48, steps = 40000, bins = 4;
    std::vector<std::vector<double>> hist(bins + 1, std::vector<double>(chains, 0.0)); // bins of u1, then u0 >= 1/2
    for (int c = 0; c < chains; ++c) {
        PrimarySampleVector u(Pcg32(10, uint64_t(c)), Pcg32(20, uint64_t(c)));
        auto eval = [&](std::vector<ImageContribution>& out) {
            out.clear();
            u.restart();
            const double u0 = u.next1D();
            const double u1 = u0 < 0.5 ? u.next1D() : -1;
            const double f = u0 < 0.5 ? 3 * u1 * u1 : 1.0;
            out.push_back({Vec2(u0, u1), Spectrum(f)});
            return targetValue(out);
        };
        ChainPosition pos;
        pos.target = eval(pos.contributions);
        ChainImage image(1.0);
        std::vector<ImageContribution> proposed;
        for (int i = 0; i < steps; ++i) {
            const bool large = u.rng().nextDouble() < 0.3;
            u.startIteration(large);
            const double f = eval(proposed);
            const double a = std::min(1.0, f / pos.target);
            const bool move = u.rng().nextDouble() < a;
            pos.step(proposed, f, a, move, image);
            if (move)
                u.accept();
            else
                u.reject();
        }
        pos.flush(image);
        for (const auto& s : image.splats()) {
            const int b = s.raster.x < 0.5 ? std::min(bins - 1, int(s.raster.y * bins)) : bins;
            hist[size_t(b)][size_t(c)] += s.value[0] / steps; // credit f/f* = 1 per unit of credit
        }
    }
    // Expected visit frequencies: 1/2 for u0 >= 1/2; (1/2) (((b+1)/4)^3 - (b/4)^3) for the u1 bins.
    for (int b = 0; b <= bins; ++b) {
        const double expected = b == bins ? 0.5 : 0.5 * (std::pow((b + 1.0) / bins, 3) - std::pow(double(b) / bins, 3));
        const auto m = meanAndError(hist[size_t(b)]);
        INFO("bin " << b << ": " << m.mean << " +- " << m.error << ", expected " << expected);
        CHECK(std::abs(m.mean - expected) < 5 * m.error);
        CHECK(m.error < 0.1 * expected); // the check above must have power
    }
}

TEST_CASE("primary-space chains in the furnace box: every pixel is Le * sum of rho^k", "[mcmc]") {
    test::TempDir dir;
    const double rho = 0.5;
    const int depth = 3;
    const auto scene = loadScene(test::furnaceBox(dir, rho, depth));
    const double exact = 1 + rho + rho * rho; // paths of 1, 2 and 3 edges
    for (const auto space : {PrimarySpace::Kelemen, PrimarySpace::Multiplexed}) {
        // Independent runs: the spread of their image means is the tolerance.
        std::vector<double> means;
        for (uint64_t seed = 0; seed < 8; ++seed)
            means.push_back(imageMean(runChains(*scene, space, depth, 24 * 24 * 16, seed)));
        const auto m = meanAndError(means);
        INFO((space == PrimarySpace::Kelemen ? "PSSMLT" : "MMLT")
             << ": " << m.mean << " +- " << m.error << ", exact " << exact);
        CHECK(std::abs(m.mean - exact) < 5 * m.error + 1e-6 * exact);
        CHECK(m.error < 0.02 * exact);
    }
}

TEST_CASE("path-space MLT in the furnace box: every pixel is Le * sum of rho^k", "[mcmc]") {
    test::TempDir dir;
    const double rho = 0.5;
    const int depth = 3;
    const auto scene = loadScene(test::furnaceBox(dir, rho, depth));
    const double exact = 1 + rho + rho * rho;
    std::vector<double> means;
    for (uint64_t seed = 0; seed < 8; ++seed)
        means.push_back(imageMean(runPathChains(*scene, depth, 24 * 24 * 16, seed)));
    const auto m = meanAndError(means);
    INFO("path-space MLT: " << m.mean << " +- " << m.error << ", exact " << exact);
    CHECK(std::abs(m.mean - exact) < 5 * m.error + 1e-6 * exact);
    CHECK(m.error < 0.02 * exact);
}

TEST_CASE("path-space MLT under a uniform environment: a convex diffuse sphere has radiance albedo * L",
          "[mcmc][long]") {
    // test_util.h's sky sphere: the sphere sends albedo * L = 1.4, the corners see the sky itself (2). The chains'
    // paths start on the environment (light vertices that are directions, moved by the bidirectional mutation from both
    // sides) and are normalized by b from BDPT, whose paths end there too. 8 independent runs; 5 standard
    // errors of their spread.
    test::TempDir dir;
    auto scene = loadScene(test::skySphere(dir));
    for (const std::string mix : {"bidirectional", "bidirectional,lens,lens-subpath"}) {
        INFO(mix);
        std::vector<double> sphere, sky;
        for (uint64_t seed = 0; seed < 8; ++seed) {
            const auto img = runPathMix(*scene, mix, 4, 32 * 32 * 1024, seed);
            double a = 0, c = 0;
            for (int y = 0; y < 32; ++y)
                for (int x = 0; x < 32; ++x) {
                    const double g = img[3 * size_t(y * 32 + x) + 1];
                    // The central 8 x 8 pixels see only the sphere, the 3 x 3 corners only the sky.
                    if (x >= 12 && x < 20 && y >= 12 && y < 20) a += g / 64;
                    if ((x < 3 || x >= 29) && (y < 3 || y >= 29)) c += g / 36;
                }
            sphere.push_back(a);
            sky.push_back(c);
        }
        const auto s = meanAndError(sphere), c = meanAndError(sky);
        INFO("sphere " << s.mean << " +- " << s.error << " (1.4), sky " << c.mean << " +- " << c.error << " (2)");
        CHECK(std::abs(s.mean - 1.4) < 5 * s.error + 1e-6);
        CHECK(std::abs(c.mean - 2.0) < 5 * c.error + 1e-6);
        CHECK(s.error < 0.02 * 1.4);
    }
}

TEST_CASE("path-space MLT under a directional light: a diffuse plane has radiance rho / pi E cos(theta)", "[mcmc]") {
    // A diffuse plane (albedo 0.5) filling the view, lit by a directional light of irradiance 3 arriving
    // 30 degrees off its normal: every pixel sees 0.5 / pi * 3 * cos 30 deg. The light vertex is the
    // light's one direction (its delta stripped): never moved, x_1 re-sampled on the scene disk along it.
    // The image's mean is b by construction (each state deposits b); the chains' distribution shows in
    // its quadrants, each of which must see the same radiance. 8 independent runs.
    test::TempDir dir;
    auto scene = loadScene(dir.write("sun.xml", R"(<scene version="0.5.0">
  <sensor type="perspective"><float name="fov" value="40"/>
    <transform name="toWorld"><lookat origin="0,0,5" target="0,0,0" up="0,1,0"/></transform>
    <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="32"/><rfilter type="box"/></film>
  </sensor>
  <emitter type="directional"><vector name="direction" x="0.5" y="0" z="-0.8660254037844386"/>
    <rgb name="irradiance" value="3"/></emitter>
  <shape type="rectangle"><transform name="toWorld"><scale value="2"/></transform>
    <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf></shape>
</scene>)"));
    const double expected = 0.5 / Pi * 3 * std::sqrt(3.0) / 2;
    std::vector<std::vector<double>> quadrants(4);
    for (uint64_t seed = 0; seed < 8; ++seed) {
        const auto img = runPathMix(*scene, "bidirectional", 2, 32 * 32 * 64, seed);
        std::vector<double> q(4, 0.0);
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 32; ++x)
                q[size_t((y / 16) * 2 + x / 16)] += img[3 * size_t(y * 32 + x) + 1] / 256;
        for (size_t k = 0; k < 4; ++k)
            quadrants[k].push_back(q[k]);
    }
    for (size_t k = 0; k < 4; ++k) {
        const auto m = meanAndError(quadrants[k]);
        INFO("quadrant " << k << ": " << m.mean << " +- " << m.error << ", expected " << expected);
        CHECK(std::abs(m.mean - expected) < 5 * m.error + 1e-6 * expected);
        CHECK(m.error < 0.02 * expected);
    }
}

TEST_CASE("path-space MLT under an envmap converges to BDPT", "[mcmc]") {
    // A sky with a bright patch (importance-sampled envmap: the light side draws directions by the map,
    // eye subpaths escape into it) over a glossy sphere on a diffuse plane.
    test::TempDir dir;
    const int W = 32, H = 16;
    std::vector<float> rgb(size_t(W) * H * 3);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const bool sun = x >= 20 && x < 23 && y >= 3 && y < 5;
            float* p = &rgb[(size_t(y) * W + size_t(x)) * 3];
            p[0] = sun ? 40.0f : 0.3f + 0.02f * float(y);
            p[1] = sun ? 35.0f : 0.4f;
            p[2] = sun ? 30.0f : 0.6f - 0.02f * float(y);
        }
    test::writeRgbExr((dir.path / "sky.exr").string(), W, H, rgb);
    auto scene = loadScene(dir.write("envmap.xml", R"(<scene version="0.5.0">
  <sensor type="perspective"><float name="fov" value="45"/>
    <transform name="toWorld"><lookat origin="0,2,5" target="0,0.5,0" up="0,1,0"/></transform>
    <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="24"/></film>
  </sensor>
  <emitter type="envmap"><string name="filename" value="sky.exr"/></emitter>
  <shape type="rectangle"><transform name="toWorld"><scale value="4"/><rotate x="1" angle="-90"/></transform>
    <bsdf type="diffuse"><rgb name="reflectance" value="0.6"/></bsdf></shape>
  <shape type="sphere"><point name="center" x="0" y="1" z="0"/><float name="radius" value="1"/>
    <bsdf type="roughconductor"><float name="alpha" value="0.3"/></bsdf></shape>
</scene>)"));
    checkAgainstBdpt(*scene, 4, 8,
                     {{"bidirectional", pathRuns(*scene, "bidirectional", 4)},
                      {"bidirectional,lens", pathRuns(*scene, "bidirectional,lens", 4)}});
}

TEST_CASE("path-space MLT with an area light and a point light under a sky converges to BDPT", "[mcmc]") {
    // The bidirectional mutation re-samples the light vertex on the area light or the sky only (a point
    // light's position stays): its light-side densities and the eye side's must be the true ones, the
    // emitter chosen among the movable ones, or the splits are weighed wrong against each other. (The
    // earlier draw among all emitters, failing on the point light while the densities divided by the
    // movable ones' share (the point light holds most of the selection here), stayed below this test's
    // resolution, with intensity 6 and 60 alike.)
    test::TempDir dir;
    auto scene = loadScene(dir.write("mixed.xml", R"(<scene version="0.5.0">
  <sensor type="perspective"><float name="fov" value="50"/>
    <transform name="toWorld"><lookat origin="0,2,5" target="0,0.5,0" up="0,1,0"/></transform>
    <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="24"/></film>
  </sensor>
  <emitter type="constant"><rgb name="radiance" value="0.3"/></emitter>
  <emitter type="point"><point name="position" x="1.5" y="2" z="1"/><rgb name="intensity" value="60"/></emitter>
  <shape type="rectangle"><transform name="toWorld"><scale value="0.3"/><rotate x="1" angle="90"/><translate x="-1" y="2.5" z="0"/></transform>
    <emitter type="area"><rgb name="radiance" value="15"/></emitter></shape>
  <shape type="rectangle"><transform name="toWorld"><scale value="4"/><rotate x="1" angle="-90"/></transform>
    <bsdf type="diffuse"><rgb name="reflectance" value="0.6"/></bsdf></shape>
  <shape type="sphere"><point name="center" x="0" y="0.8" z="0"/><float name="radius" value="0.8"/>
    <bsdf type="diffuse"><rgb name="reflectance" value="0.8"/></bsdf></shape>
</scene>)"));
    checkAgainstBdpt(*scene, 4, 8, {{"bidirectional", pathRuns(*scene, "bidirectional", 4)}});
}

TEST_CASE("path-space MLT on glossy-sky (a constant environment and an area light) converges to BDPT", "[mcmc]") {
    auto scene = loadScene(test::shippedScene("glossy-sky"));
    checkAgainstBdpt(*scene, 6, 8,
                     {{"bidirectional", pathRuns(*scene, "bidirectional", 6)},
                      {"bidirectional,lens", pathRuns(*scene, "bidirectional,lens", 6)}});
}

TEST_CASE("chains are bit-identical whatever the thread count", "[mcmc]") {
    test::TempDir dir;
    const auto scene = loadScene(test::furnaceBox(dir, 0.5, 3));
    for (const auto space : {PrimarySpace::Kelemen, PrimarySpace::Multiplexed})
        CHECK(runChains(*scene, space, 3, 5000, 3, 1, 2000) == runChains(*scene, space, 3, 5000, 3, 2, 2000));
    CHECK(runPathChains(*scene, 3, 5000, 3, 1, 2000) == runPathChains(*scene, 3, 5000, 3, 2, 2000));
}

TEST_CASE("bidirectional mutation: the density it samples with is the one T(x -> y) is computed from", "[mcmc]") {
    // For many current paths, propose, and compare the density the proposal
    // multiplied while sampling with the one recomputed from the two paths alone; on a scene with glass
    // and mirror spheres (specular vertices in both directions), on the diffuse cornell-box, and on
    // glossy-sky (a constant environment: light vertices that are directions, sampled from the light side
    // and by eye subpaths that escape).
    for (const std::string name : {"cornell-spheres", "cornell-box", "glossy-sky"}) {
        auto scene = loadScene(test::shippedScene(name));
        scene->camera = scene->camera.withResolution(32, 32);
        PathSettings b;
        b.maxDepth = 8;
        const auto seeds = seedWithBdpt(*scene, b, 20000, name == "cornell-box" ? 50 : 5000, 1, RunControl(2));
        const BidirectionalMutation bidir(*scene, 8);
        Pcg32 rng(3, 3);
        int checked = 0, specular = 0, off = 0, dropped = 0, sky = 0;
        double worst = 0, worstNearContact = 0;
        // The shortest edge of a path between two surface points, relative to the scene.
        const auto shortestEdge = [&](const MarkovPath& path) {
            double shortest = std::numeric_limits<double>::infinity();
            for (size_t k = 0; k + 1 < path.v.size(); ++k)
                if (!path.v[k].infinite && !path.v[k + 1].infinite)
                    shortest = std::min(shortest, length(path.v[k + 1].p() - path.v[k].p()));
            return shortest / scene->sceneRadius();
        };
        for (size_t i = 0; i < seeds.paths.size(); ++i) {
            const auto state = stateOf(*scene, seeds.paths[i], i);
            if (!state) continue;
            const MarkovPath& x = *state;
            // On the sphere scene, start from paths through the glass or the mirror, so that specular
            // vertices are kept, deleted and re-sampled.
            bool throughSpecular = false;
            for (const auto& v : x.v)
                throughSpecular |= isSpecular(v);
            if (name == "cornell-spheres" && !throughSpecular) continue;
            for (int j = 0; j < 100; ++j) {
                Proposal p;
                bidir.propose(x, rng, p);
                if (p.failed) continue;
                ++checked;
                sky += p.y.v[0].infinite;
                for (const auto& v : p.y.v)
                    specular += isSpecular(v);
                INFO(name << ": path " << i << ", " << x.edges() << " -> " << p.y.edges() << " edges");
                REQUIRE(p.sampledDensity > 0);
                if (p.recomputedDensity == 0) {
                    // A specular vertex whose recomputed directions miss deltaEval's 1e-6 tolerance: the
                    // density function says y cannot be proposed, so Q(x -> y) = 0 and it is rejected.
                    // That keeps detailed balance (the kernel is the one the density function defines)
                    // at the price of a rejection; it must stay rare.
                    ++dropped;
                    CHECK(p.forwardQ == 0);
                    continue;
                }
                const double mismatch = std::abs(p.recomputedDensity / p.sampledDensity - 1);
                const bool nearContact = std::min(shortestEdge(x), shortestEdge(p.y)) < 1e-2;
                double& worstHere = nearContact ? worstNearContact : worst;
                worstHere = std::max(worstHere, mismatch);
                off += mismatch > 1e-3;
                CHECK(p.forwardQ > 0);
                CHECK(std::isfinite(p.reverseQ));
                // On diffuse paths the reverse move always exists (same range, lengths swapped); a specular
                // vertex in the old range can make it impossible (no split connects around it): a = 0.
                if (name != "cornell-spheres") CHECK(p.reverseQ > 0);
            }
        }
        INFO(name << ": " << checked << " proposals checked, " << specular << " specular vertices in them, " << sky
                  << " lit by the sky; " << off << " densities off by more than 1e-3, the worst by " << worst << " (by "
                  << worstNearContact << " with an edge shorter than 1 % of the scene); " << dropped << " dropped");
        CHECK(dropped < checked / 50);
        CHECK(checked > 1000);
        // Rays leave surfaces from an offset origin (scene/ray.h) and hits carry float barycentrics, so the
        // new vertex is not exactly on the sampled direction seen from the old one: on the edges of 1e-3
        // to 1e-4 where a sphere touches the floor the densities differ by tens of percent (the error is
        // relative to the edge; how much depends on the compiler's rounding), elsewhere mostly by less than
        // 1e-4 (0.5 % of the proposals beyond 1e-3). A wrong measure, transport mode or factor would be off on
        // most proposals, and by a factor on every path through some strategy, which the bound on edges over
        // 1 % of the scene's radius catches (an error of 1e-4 of the scene turns their densities by ~1e-2).
        CHECK(off < checked / 100);
        CHECK(worst < 0.2);
        if (name == "cornell-spheres") CHECK(specular > 100);
        if (name == "glossy-sky") CHECK(sky > 500);
    }
}

TEST_CASE("PSSMLT, MMLT and path-space MLT converge to BDPT on the public cornell-box", "[mcmc][slow]") {
    auto scene = loadScene(test::shippedScene("cornell-box"));
    checkAgainstBdpt(*scene, 4, 6,
                     {{"PSSMLT", primaryRuns(*scene, PrimarySpace::Kelemen, 4)},
                      {"MMLT", primaryRuns(*scene, PrimarySpace::Multiplexed, 4)},
                      {"path-space MLT", pathRuns(*scene, "bidirectional", 4)}});
}

TEST_CASE("PSSMLT, MMLT and path-space MLT converge to BDPT on the public veach-bidir", "[mcmc][slow]") {
    // The glass egg's caustic and the lamps' small lights: the scene the chains are meant for.
    auto scene = loadScene(test::shippedScene("veach-bidir"));
    checkAgainstBdpt(*scene, 5, 6,
                     {{"PSSMLT", primaryRuns(*scene, PrimarySpace::Kelemen, 5)},
                      {"MMLT", primaryRuns(*scene, PrimarySpace::Multiplexed, 5)},
                      {"path-space MLT", pathRuns(*scene, "auto", 5)}});
}

TEST_CASE("path-space MLT converges to BDPT through glass and mirror spheres", "[mcmc][slow]") {
    // Specular vertices kept, deleted and re-sampled from both sides (markov_path.h's stripped deltas).
    auto scene = loadScene(test::shippedScene("cornell-spheres"));
    checkAgainstBdpt(*scene, 5, 6, {{"path-space MLT", pathRuns(*scene, "bidirectional", 5)}});
}

TEST_CASE("a seed path's f / p recomputed from scratch equals the BDPT contribution it was stored with", "[mcmc]") {
    // The record of strategy (s, t) stores BDPT's unweighted f / p. Re-created from its vertices alone,
    // f~ / p~ of the same split (s light-side vertices, the rest from the eye) must give the same value
    // (times the pixel count, markov_path.h; camera strategies also by the crop-to-sensor density ratio):
    // this ties the delta stripping of specular vertices to BDPT's throughput weights.
    // On cornell-spheres (specular vertices), glossy-sky (a constant environment: escaped camera paths,
    // s = 0, and light vertices that are directions in solid angle, s >= 1) and a sphere on a plane under a
    // directional light (its direction's delta stripped).
    test::TempDir dir;
    const std::string sun = dir.write("sun.xml", R"(<scene version="0.5.0">
  <sensor type="perspective"><float name="fov" value="40"/>
    <transform name="toWorld"><lookat origin="0,3,5" target="0,0,0" up="0,1,0"/></transform>
    <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="32"/></film>
  </sensor>
  <emitter type="directional"><vector name="direction" x="0.4" y="-1" z="-0.3"/><rgb name="irradiance" value="3"/></emitter>
  <shape type="rectangle"><transform name="toWorld"><scale value="3"/><rotate x="1" angle="-90"/></transform>
    <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf></shape>
  <shape type="sphere"><point name="center" x="0" y="1" z="0"/><float name="radius" value="1"/>
    <bsdf type="roughconductor"><float name="alpha" value="0.2"/></bsdf></shape>
</scene>)");
    for (const std::string name : {"cornell-spheres", "glossy-sky", "sun"}) {
        INFO(name);
        auto scene = loadScene(name == "sun" ? sun : test::shippedScene(name));
        scene->camera = scene->camera.withResolution(32, 32);
        PathSettings b;
        b.maxDepth = 6;
        const auto seeds = seedWithBdpt(*scene, b, 20000, 3000, 2, RunControl(2));
        const SensorWindow sensor(scene->camera);
        const double pixels = 32 * 32;
        int checked = 0, specular = 0, bad = 0, sky = 0;
        for (size_t i = 0; i < seeds.paths.size(); ++i) {
            const auto& rec = seeds.paths[i];
            const auto state = stateOf(*scene, rec, i);
            if (!state) continue;
            const MarkovPath& x = *state;
            const int k = x.edges();
            // The delta-stripped density of sampling x the way its record's strategy did: s vertices from
            // the light side (the first one chosen among all emitters, as BDPT does), the rest from the eye
            // (the bidirectional mutation's split densities, newVertexDensity, without its choice among
            // the emitters whose vertex moves).
            double split = 1;
            for (int i = 0; i < k; ++i)
                split *= i < rec.s ? densityFromLight(*scene, x.v, size_t(i))
                                   : densityFromEye(*scene, sensor, x.v, size_t(i));
            const Spectrum c(rec.contribution[0], rec.contribution[1], rec.contribution[2]);
            const double expected = pixels * c.luminance() / (rec.t >= 2 ? sensor.cropToSensorDensity() : 1.0);
            if (!(split > 0) || !(expected > 0)) continue;
            ++checked;
            bool hasSpecular = false;
            for (const auto& v : x.v)
                hasSpecular |= isSpecular(v);
            specular += hasSpecular;
            sky += x.v[0].infinite;
            const double ratio = x.target / split / expected;
            if (std::abs(ratio - 1) > 1e-3) {
                ++bad;
                UNSCOPED_INFO("path " << i << " (s = " << rec.s << ", t = " << rec.t << ", specular " << hasSpecular
                                      << "): ratio " << ratio);
            }
        }
        INFO(checked << " paths checked, " << specular << " with specular vertices, " << sky
                     << " lit from infinity (sky or sun)");
        CHECK(checked > 1000);
        if (name == "cornell-spheres") CHECK(specular > 50);
        if (name != "cornell-spheres") CHECK(sky > 300);
        CHECK(bad <= checked / 100);
    }
}

// ---- Veach's perturbations (Veach thesis 11.4.3-11.4.4) ----

TEST_CASE("a chain state's specular chains are the same from its vertices and from its record; a record "
          "that does not fit the scene is refused naming it",
          "[mcmc][manifold]") {
    auto scene = loadScene(test::shippedScene("cornell-spheres"), {{"res", "32"}});
    PathSettings b;
    b.maxDepth = 6;
    const auto seeds = seedWithBdpt(*scene, b, 20000, 400, 3, RunControl(2));
    size_t withChains = 0;
    for (size_t i = 0; i < seeds.paths.size(); ++i) {
        const auto x = stateOf(*scene, seeds.paths[i], i);
        if (!x) continue;
        const auto fromMemory = specularChains(x->v);
        const auto fromRecord = specularChains(*scene, toPathRecord(*scene, *x, 0, 0), "state");
        REQUIRE(fromMemory.size() == fromRecord.size());
        for (size_t c = 0; c < fromMemory.size(); ++c) {
            CHECK(fromMemory[c].first == fromRecord[c].first);
            CHECK(fromMemory[c].last == fromRecord[c].last);
            REQUIRE(fromMemory[c].chain.size() == fromRecord[c].chain.size());
            CHECK(fromMemory[c].chain.size() == fromMemory[c].last - fromMemory[c].first + 1);
            for (size_t j = 0; j < fromMemory[c].chain.size(); ++j)
                CHECK(length(fromMemory[c].chain[j].p - fromRecord[c].chain[j].p) == 0);
        }
        withChains += !fromMemory.empty();
    }
    CHECK(withChains >= 20); // the glass and mirror spheres: most seed paths pass through one
    const auto longer =
        std::find_if(seeds.paths.begin(), seeds.paths.end(), [](const auto& p) { return p.vertices.size() >= 3; });
    REQUIRE(longer != seeds.paths.end());
    auto bad = *longer;
    bad.vertices[1].prim = 1u << 30;
    CHECK(errorOf([&] { (void)verticesFromRecord(*scene, bad, "bad.ltp path 0"); }) ==
          "bad.ltp path 0: names a primitive its shape lacks");
}

namespace {

// The perturbation (or lens-subpath mutation) of a name, for the scene and paths of up to maxEdges.
std::unique_ptr<Mutation> makePerturbation(const std::string& name, const Scene& scene, int maxEdges) {
    if (name == "lens") return std::make_unique<LensPerturbation>(scene);
    if (name == "lens-subpath") return std::make_unique<LensSubpathMutation>(scene, maxEdges);
    if (name == "caustic") return std::make_unique<CausticPerturbation>(scene);
    return std::make_unique<MultiChainPerturbation>(scene);
}

} // namespace

TEST_CASE("lens, caustic, multi-chain perturbations, lens subpath: the density sampled is the T(x -> y) computed",
          "[mcmc]") {
    // From seed paths of each perturbation's type, propose; the density multiplied
    // while tracing (camera raster or turned direction, then the specular chain with the lobes fixed) must
    // be the one recomputed from y alone, and both Q finite. Detailed balance: the reverse move's parameters
    // rebuilt from the two paths (raster offset |u - u'|, angle between the old and new directions, the
    // caustic ranges taken at y) give T(y -> x) = reverseQ f*(x). The lens-subpath mutation samples its
    // lobes and where it stops: its density includes those choices.
    // sun-caustic: every light vertex at infinity (a sky direction, or the sun's, whose ray the caustic
    // perturbation moves sideways).
    const std::pair<const char*, std::vector<std::string>> cases[] = {
        {"cornell-spheres", {"lens", "caustic", "multi-chain", "lens-subpath"}}, {"sun-caustic", {"lens", "caustic"}}};
    for (const auto& [sceneName, names] : cases) {
        INFO(sceneName);
        const auto [scene, seeds] = test::seededScene(sceneName, 8, 40000, 6000, 1);
        std::vector<MarkovPath> paths;
        for (size_t i = 0; i < seeds.paths.size(); ++i)
            if (auto x = stateOf(*scene, seeds.paths[i], i)) paths.push_back(std::move(*x));
        const SensorWindow sensor(scene->camera);
        for (const std::string& name : names) {
            const auto mutation = makePerturbation(name, *scene, 8);
            Pcg32 rng(7, 7);
            int suitable = 0, checked = 0, failed = 0, off = 0, balanceOff = 0, specular = 0, fromInfinity = 0;
            double worst = 0, acceptance = 0;
            for (const auto& x : paths) {
                if (!mutation->suitable(x)) continue;
                ++suitable;
                for (int j = 0; j < 20; ++j) {
                    Proposal p;
                    mutation->propose(x, rng, p);
                    if (p.failed) {
                        ++failed;
                        continue;
                    }
                    ++checked;
                    // The caustic perturbation's sideways move: its chain starts at the light at infinity.
                    fromInfinity += name == "caustic" && x.v[size_t(CausticPerturbation::chainStart(x))].infinite;
                    for (const auto& v : p.y.v)
                        specular += isSpecular(v);
                    const double mismatch = proposalDensityMismatch(*mutation, p);
                    worst = std::max(worst, mismatch);
                    off += mismatch > 1e-3;
                    acceptance += std::min(1.0, p.reverseQ / p.forwardQ);
                    // The reverse move rebuilt from the paths alone.
                    double reverseT = 0, rebuiltTheta = 0;
                    if (name == "caustic") {
                        const auto& caustic = static_cast<const CausticPerturbation&>(*mutation);
                        const int l = CausticPerturbation::chainStart(x);
                        const Vec3 a = x.v[size_t(l)].directionTo(x.v[size_t(l) + 1]);
                        const Vec3 c = p.y.v[size_t(l)].directionTo(p.y.v[size_t(l) + 1]);
                        double step = std::atan2(length(cross(a, c)), dot(a, c));
                        if (x.v[size_t(l)].infinite) { // the parallel ray moved sideways: x_1's offset across it
                            const Vec3 d = p.y.v[1].p() - x.v[1].p();
                            step = length(d - a * dot(d, a));
                        }
                        reverseT = caustic.chainDensity(x, caustic.stepDensity(p.y, step));
                        rebuiltTheta = step / caustic.steps(p.y).lo;
                        // Near a range's end the rebuilt angle may fall on the other side of it.
                        if (reverseT == 0 && p.reverseQ == 0) continue;
                    } else {
                        const double r = length(p.y.raster - x.raster);
                        const double pOffset = rasterRadii(scene->camera).planeDensity(r);
                        if (name == "lens-subpath") {
                            reverseT = static_cast<const LensSubpathMutation&>(*mutation).subpathDensity(
                                x.v, firstNonSpecularFromEye(x.v));
                        } else if (name == "lens") {
                            reverseT = pOffset * eyeChainDensity(*scene, sensor, x.v, firstNonSpecularFromEye(x.v));
                        } else {
                            // Each turned direction: the angle between the old and the new one at the stop. Turns of
                            // 1e-6 rad are not recoverable from float hit points, but the kernel is the same both
                            // ways: compare T(y -> x) / T(x -> y) rebuilt, with the rebuilt angles in both.
                            const auto stops = MultiChainPerturbation::stops(x);
                            std::vector<double> thetas;
                            for (size_t s = 0; s + 1 < stops.size(); ++s) {
                                const size_t d = size_t(stops[s]);
                                const Vec3 a = x.v[d].directionTo(x.v[d - 1]);
                                const Vec3 c = p.y.v[d].directionTo(p.y.v[d - 1]);
                                thetas.push_back(std::atan2(length(cross(a, c)), dot(a, c)));
                            }
                            const auto& multi = static_cast<const MultiChainPerturbation&>(*mutation);
                            if (multi.density(p.y, pOffset, thetas) == 0) continue; // a turn below float precision
                            reverseT = multi.density(x, pOffset, thetas) / multi.density(p.y, pOffset, thetas) *
                                       p.forwardQ * p.y.target;
                        }
                    }
                    // Rebuilt from hit points (float barycentrics, offset ray origins): within 1 %; the caustic's
                    // rebuilt angle carries the ray-origin offset, 1-2 % of theta near theta1 (measured), so 5 %.
                    const double balance = std::abs(reverseT / (p.reverseQ * x.target) - 1);
                    if (!(balance < (name == "caustic" ? 5e-2 : 1e-2))) {
                        ++balanceOff;
                        UNSCOPED_INFO(name << ": reverse density off by " << balance << ", theta / theta1 "
                                           << rebuiltTheta);
                    }
                }
            }
            INFO(name << ": " << suitable << " suitable seed paths, " << checked << " proposals checked (" << failed
                      << " failed), " << specular << " specular vertices; " << off
                      << " densities off by more than 1e-3, the worst by " << worst << "; " << balanceOff
                      << " reverse densities off by more than 1 %; mean acceptance "
                      << acceptance / std::max(1, checked));
            CHECK(checked > (name == "multi-chain" ? 100 : 1000));
            if (name == "caustic" || name == "multi-chain") CHECK(specular > checked); // through a specular chain
            if (name == "lens-subpath") CHECK(specular > checked / 20); // lens subpaths through the spheres
            // Tolerances as in the bidirectional test (offset ray origins and float hit points); a wrong measure,
            // transport mode or lobe factor would be off on most proposals.
            CHECK(off < checked / 100 + 1);
            CHECK(worst < 0.5);
            CHECK(balanceOff < checked / 100 + 1);
            if (std::string(sceneName) == "sun-caustic" && name == "caustic") CHECK(fromInfinity > checked / 2);
        }
    }
}

TEST_CASE("each perturbation mixed with the bidirectional mutation converges to BDPT", "[mcmc][slow]") {
    // The lens perturbation on the diffuse cornell-box and on the spheres, the caustic and
    // multi-chain perturbations where their paths occur (glass and mirror spheres), the lens-subpath
    // mutation through the spheres seen by the camera, the manifold perturbation through both (caustics
    // seen directly and through the glass), and the caustic and manifold perturbations under a sky and a
    // sun (light vertices at infinity). Each must also have moved the chains.
    std::vector<MutationStatistics> stats(8);
    {
        auto scene = loadScene(test::shippedScene("cornell-box"));
        checkAgainstBdpt(*scene, 4, 6, {{"bidirectional,lens", pathRuns(*scene, "bidirectional,lens", 4, &stats[0])}});
    }
    auto scene = loadScene(test::shippedScene("cornell-spheres"));
    checkAgainstBdpt(*scene, 5, 6,
                     {{"bidirectional,lens", pathRuns(*scene, "bidirectional,lens", 5, &stats[1])},
                      {"bidirectional,caustic", pathRuns(*scene, "bidirectional,caustic", 5, &stats[2])},
                      {"bidirectional,multi-chain", pathRuns(*scene, "bidirectional,multi-chain", 5, &stats[3])},
                      {"bidirectional,lens-subpath", pathRuns(*scene, "bidirectional,lens-subpath", 5, &stats[4])},
                      {"bidirectional,manifold", pathRuns(*scene, "bidirectional,manifold", 5, &stats[5])}});
    auto sun = loadScene(test::shippedScene("sun-caustic"));
    checkAgainstBdpt(*sun, 5, 6,
                     {{"bidirectional,caustic", pathRuns(*sun, "bidirectional,caustic", 5, &stats[6])},
                      {"bidirectional,manifold", pathRuns(*sun, "bidirectional,manifold", 5, &stats[7])}});
    for (const auto& st : stats) {
        INFO(st.text());
        REQUIRE(st.strategies().size() == 2);
        CHECK(st[0].accepted > 0);
        CHECK(st[1].accepted > 0);
    }
}

TEST_CASE(
    "strategy selection: auto leaves out caustic, multi-chain and manifold without specular chains (manifold also "
    "without glossy ones), names are checked",
    "[mcmc]") {
    SceneFeatures diffuse;
    diffuse.specularReason = "no delta BSDF";
    diffuse.portalReason = "no shape marked portal";
    const auto a = chooseMutations("auto", diffuse);
    REQUIRE(a.chosen.size() == 2);
    CHECK(a.chosen[1].name == "lens");
    const auto saysWhy = [&](const std::string& text) {
        return std::any_of(a.leftOut.begin(), a.leftOut.end(),
                           [&](const std::string& why) { return why.find(text) != std::string::npos; });
    };
    CHECK(saysWhy("caustic, multi-chain perturbations: no delta BSDF"));
    CHECK(saysWhy("manifold perturbation: no delta or glossy BSDF"));
    SceneFeatures glossy = diffuse;
    glossy.glossySurfaces = true;
    const auto g = chooseMutations("auto", glossy);
    REQUIRE(g.chosen.size() == 3);
    CHECK(g.chosen[2].name == "manifold");
    SceneFeatures glass = diffuse;
    glass.specularChains = true;
    CHECK(chooseMutations("auto", glass).chosen.size() == 5);
    CHECK(chooseMutations("auto", glass).chosen[4].name == "manifold");
    const auto w = chooseMutations("bidirectional,lens:2,caustic", glass);
    CHECK(w.chosen[1].weight == 2);
    CHECK(w.chosen[2].weight == 1);
    CHECK(chooseMutations("bidirectional,lens-subpath", glass).chosen[1].name == "lens-subpath");
    CHECK(saysWhy("portal perturbation: no shape marked portal"));
    SceneFeatures window = diffuse;
    window.hasPortals = true;
    const auto p = chooseMutations("auto", window);
    REQUIRE(p.chosen.size() == 3);
    CHECK(p.chosen[2].name == "portal");
    CHECK_THROWS_WITH(chooseMutations("bidirectional,portals", glass), Catch::Contains("unknown mutation"));
    CHECK_THROWS_WITH(chooseMutations("lens,caustic", glass), Catch::Contains("bidirectional"));
}

TEST_CASE("a path with two coincident vertices carries no light and evaluates no BSDF toward a zero-length edge",
          "[mcmc]") {
    // A bidirectional mutation on kitchen-window (a counter top lying on the counter) proposed a path with two
    // vertices at one point; evaluatePath then evaluated the rough plastic there toward the NaN direction of the
    // zero-length edge before checking that edge, and the coating's table lookup read memory anywhere (a segfault
    // after a minute of a 90 s run). Each edge is now checked before either end is evaluated along it, and the
    // lookup takes a NaN cosine to 0. Broken on purpose: with both reverted this test died of SIGSEGV (Release).
    TempDir dir;
    auto scene = loadScene(dir.write("plastic.xml", R"(<scene version="0.5.0">
  <sensor type="perspective"><float name="fov" value="60"/>
    <transform name="toWorld"><lookat origin="0,1,2" target="0,0,0" up="0,1,0"/></transform>
    <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/></film>
  </sensor>
  <shape type="rectangle"><transform name="toWorld"><scale value="3"/><rotate x="1" angle="-90"/></transform>
    <bsdf type="roughplastic"><float name="alpha" value="0.1"/></bsdf></shape>
  <shape type="rectangle"><transform name="toWorld"><rotate x="1" angle="90"/><translate y="2"/></transform>
    <emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>
</scene>)"));
    const auto floor = traceVertex(*scene, Ray{Vec3(0.1, 1, 0.2), Vec3(0, -1, 0)});
    const auto lamp = traceVertex(*scene, Ray{Vec3(0, 1, 0), Vec3(0, 1, 0)});
    REQUIRE(floor);
    REQUIRE(lamp);
    REQUIRE(lamp->emitter);
    PathVertex camera;
    camera.type = VertexType::Camera;
    camera.si.p = scene->camera.position();
    MarkovPath x;
    x.v = {lightVertexAt(*scene, size_t(lamp->emitterIndex), lamp->p(), lamp->ng(), lamp->si.prim, lamp->si.coords),
           *floor, *floor, camera};
    const auto why = evaluatePath(*scene, x);
    REQUIRE(why);
    CHECK(*why == RejectCause::ZeroContribution);
    CHECK(x.f.isBlack());
    // Without the repeated vertex the same path carries light: the scene is not black.
    x.v.erase(x.v.begin() + 2);
    CHECK_FALSE(evaluatePath(*scene, x));
    CHECK(x.target > 0);
}
