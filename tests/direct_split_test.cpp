// The direct split (sampling/direct_split.h): paths of one and two edges rendered by path tracing, the chains' target,
// start-up, seeds and b without them, the image their sum. Checked against analytic values in the furnace (where
// each part is known exactly) for the three chain spaces, and against BDPT on a scene built like the public pool
// scenes, where a tiny lamp seen directly holds most of the image's energy.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "bsdf/bsdf.h"
#include "run/mlt_job.h"
#include "chain_runs.h"
#include "test_util.h"

using namespace lt;
using namespace lt::test;

namespace {

// The mean over the image of the channel named `name` of a buffer.
double channelMean(const file::Buffer& b, const std::string& name) {
    for (size_t c = 0; c < b.channels.size(); ++c)
        if (b.channels[c] == name) {
            double sum = 0;
            for (const float v : b.planes[c])
                sum += v;
            return sum / double(b.planes[c].size());
        }
    FAIL("no channel " << name);
    return 0;
}

MltOutcome runJob(const Scene& scene, ChainSpace space, int directSamples, int maxDepth, uint64_t mutations,
                  uint64_t seed) {
    MltSettings s;
    s.space = space;
    s.direct.samples = directSamples;
    s.paths.maxDepth = maxDepth;
    s.run.mutations = mutations;
    s.run.chains = 64;
    s.run.seed = seed;
    s.startupSamples = 20000;
    MltJob job(scene, s, std::nullopt);
    return job.run(RunControl(2));
}

const char* spaceName(ChainSpace s) {
    return s == ChainSpace::Path ? "path space" : s == ChainSpace::Primary ? "PSSMLT" : "MMLT";
}

} // namespace

TEST_CASE("the direct split in the furnace: the direct part holds the paths of 1 and 2 edges, the chains' b the rest, "
          "the image their sum",
          "[mcmc][direct]") {
    // Walls that emit 1 and reflect rho: paths of k edges bring rho^(k - 1) to every pixel. With maxDepth 4 the image is
    // 1 + rho + rho^2 + rho^3, the direct part 1 + rho and the chains' b (per pixel) rho^2 + rho^3, each exactly.
    // Tolerances: b's own standard error (its independent samples, mcmc/normalization.h) for b; for the direct part
    // and the whole image the spread of four independent runs.
    // Broken on purpose: b left with the paths of the direct part (the start-up's BDPT without minDepth) gave b per
    // pixel 1.87 and an image of 3.37 in every space; the direct part not added gave an image of 0.375.
    TempDir dir;
    const double rho = 0.5;
    const auto scene = loadScene(furnaceBox(dir, rho, 4));
    scene->camera = scene->camera.withResolution(12, 12);
    const double pixels = 144, direct = 1 + rho, chains = rho * rho + rho * rho * rho;
    for (const ChainSpace space : {ChainSpace::Path, ChainSpace::Primary, ChainSpace::Multiplexed}) {
        std::vector<double> images, directs;
        for (uint64_t seed = 0; seed < 4; ++seed) {
            const MltOutcome out = runJob(*scene, space, 16, 4, uint64_t(pixels) * 64, seed);
            const NormalizationEstimate& b = out.stats.normalization;
            INFO(spaceName(space) << ", seed " << seed << ": b per pixel " << b.b() / pixels << " +- "
                                  << b.relativeStandardError() * b.b() / pixels << ", exact " << chains);
            CHECK(std::abs(b.b() / pixels - chains) < 5 * b.relativeStandardError() * b.b() / pixels);
            CHECK(out.stats.health.nonFinite == 0);
            images.push_back(channelMean(out.image, "R"));
            directs.push_back(channelMean(out.image, "direct.R"));
        }
        const MeanAndError image = meanAndError(images), d = meanAndError(directs);
        INFO(spaceName(space) << ": image " << image.mean << " +- " << image.error << " (exact " << direct + chains
                              << "), direct part " << d.mean << " +- " << d.error << " (exact " << direct << ")");
        // 1e-6: the planes are stored as float.
        CHECK(std::abs(d.mean - direct) < 5 * d.error + 1e-6 * direct);
        CHECK(std::abs(image.mean - (direct + chains)) < 5 * image.error + 1e-6 * (direct + chains));
        CHECK(image.error < 0.01 * (direct + chains));
    }
}

namespace {

// Mean luminance over the pixels of regions 0 and 1 (region[i]: 0 lit above the water, 1 the lamp, 2 left out), for one
// image given as R, G, B planes.
std::array<double, 2> regionMeans(const std::vector<std::vector<float>>& rgb, const std::vector<int>& region) {
    std::array<double, 2> sum{}, count{};
    for (size_t i = 0; i < region.size(); ++i) {
        if (region[i] > 1) continue;
        sum[size_t(region[i])] += Spectrum(rgb[0][i], rgb[1][i], rgb[2][i]).luminance();
        count[size_t(region[i])] += 1;
    }
    return {sum[0] / count[0], sum[1] / count[1]};
}

} // namespace

TEST_CASE("on a pool under a tiny lamp seen directly, every chain space with the direct split lands on BDPT on the "
          "lamp and around it",
          "[mcmc][direct][slow]") {
    // scenes/lamp-pool at 32 x 24 with a smaller lamp of the same power (radius 0.008: about 1/60 of its pixel, so a
    // camera sample finds it with probability ~2e-5) and a black pool (no L S D S E light through the water, the case
    // of manifold next-event estimation, which leaves every method here with a rare-event estimate): the lamp holds
    // most of the image's energy, as on the public pool scene. Regions: the lamp's pixel (where its center projects)
    // and around it the pixels whose camera ray hits a diffuse surface (walls and ceiling). Bound: |difference|
    // under 5 standard errors of the two means over independent runs (6 of each); around the lamp also within 5 %
    // (the issue's bar; the lamp's own pixel is a rare event for BDPT and the direct part alike, the z-bound only).
    // Without the split (--direct-samples -1) the same runs gave around the lamp, against BDPT's 0.06730 +- 0.00008:
    // PSSMLT 0.468 +- 0.273, path space 0.097 +- 0.058, MMLT 0.0723 +- 0.0046 (its per-length scale keeps most of it):
    // the runs whose samples of b hit the lamp scaled everything by it. With the split: 0.0672 to 0.0673.
    auto scene = loadScene(shippedScene("lamp-pool"), {{"lampRadius", "0.008"},
                                                        {"lampRadiance", "39062, 35156, 29297"},
                                                        {"poolReflectance", "0"}});
    scene->camera = scene->camera.withResolution(32, 24);
    const int depth = 8, runs = 6;
    const size_t pixels = 32 * 24;
    std::vector<std::vector<std::vector<float>>> reference; // BDPT's R, G, B planes of each run
    for (int r = 0; r < runs; ++r)
        reference.push_back(bdptFilm(*scene, depth, 256, 100 + uint64_t(r)).developPlanes());
    // The lamp's pixel: where its center projects. Around it: the pixels whose camera ray hits a diffuse surface.
    const Vec3 eye = scene->camera.position();
    const auto lamp = scene->camera.rasterPosition(eye, normalize(Vec3(0.7, 1.7, 0.2) - eye));
    REQUIRE(lamp);
    std::vector<int> region(pixels, 2);
    for (size_t i = 0; i < pixels; ++i) {
        const Vec2 raster(double(i % 32) + 0.5, double(i / 32) + 0.5);
        const auto hit = scene->intersect(scene->camera.generateRay(raster, eye));
        const Bsdf* bsdf = hit ? scene->bsdfOf(*hit) : nullptr;
        if (bsdf && bsdf->hasDiffuse()) region[i] = 0;
    }
    region[size_t(lamp->y) * 32 + size_t(lamp->x)] = 1;
    std::vector<double> refOut, refIn;
    for (const auto& rgb : reference) {
        const auto m = regionMeans(rgb, region);
        refOut.push_back(m[0]);
        refIn.push_back(m[1]);
    }
    const MeanAndError ro = meanAndError(refOut), ri = meanAndError(refIn);
    INFO("BDPT: around the lamp " << ro.mean << " +- " << ro.error << ", lamp " << ri.mean << " +- " << ri.error);
    for (const ChainSpace space : {ChainSpace::Path, ChainSpace::Primary, ChainSpace::Multiplexed}) {
        std::vector<double> out, in;
        for (uint64_t seed = 0; seed < uint64_t(runs); ++seed) {
            const MltOutcome o = runJob(*scene, space, 16, depth, pixels * 256, seed);
            const std::vector<std::vector<float>> rgb(o.image.planes.begin(), o.image.planes.begin() + 3);
            const auto m = regionMeans(rgb, region);
            out.push_back(m[0]);
            in.push_back(m[1]);
        }
        const MeanAndError mo = meanAndError(out), mi = meanAndError(in);
        INFO(spaceName(space) << ": around the lamp " << mo.mean << " +- " << mo.error << ", lamp " << mi.mean << " +- "
                              << mi.error);
        CHECK(std::abs(mo.mean - ro.mean) < 5 * std::hypot(mo.error, ro.error));
        CHECK(std::abs(mo.mean / ro.mean - 1) < 0.05);
        CHECK(std::abs(mi.mean - ri.mean) < 5 * std::hypot(mi.error, ri.error));
    }
}

TEST_CASE("MMLT warns when a length's b_k is known too poorly for the regions it lights", "[mcmc][direct]") {
    // tiny-lamp at 24 x 24 without the direct split: the lamp seen directly (length 1) holds 85 % of b, but the
    // start-up's samples of that length hit it a few times only, so b_1 is known to +- 13 %; each length's image is
    // scaled by its own b_k (chain_run.h), so the lamp's pixels carry b_1's error and MMLT must name that length.
    // With the split the chains have no length 1, and on cornell-box at the default start-up every length holding
    // over 10 % of b is known to under 1.2 %: no warning (the check that the rule is not always on; with the rule's
    // share at 1 % it warned there of length 7, 3 % of b +- 2.8 %, which lights no region alone). Also tried:
    // a start-up of 20 samples a length missed the lamp (b_1 = 0, nothing to warn of; the missed-length test of
    // mcmc_hard_scenes_test.cpp covers that case).
    const auto warned = [](const MltOutcome& out) {
        for (const std::string& n : out.notes)
            if (n.find("by its own b_k") != std::string::npos) return n;
        return std::string();
    };
    auto tiny = loadScene(shippedScene("tiny-lamp"));
    tiny->camera = tiny->camera.withResolution(24, 24);
    MltSettings s;
    s.space = ChainSpace::Multiplexed;
    s.direct.samples = -1;
    s.paths.maxDepth = tiny->integrator.maxDepth;
    s.run.mutations = 24 * 24 * 16;
    s.run.chains = 16;
    const MltOutcome poor = MltJob(*tiny, s, std::nullopt).run(RunControl(2));
    INFO("b_1 " << poor.stats.normalization.stratumB(1) << " +- " << poor.stats.normalization.stratumStandardError(1)
                << " of b " << poor.stats.normalization.b());
    const std::string w = warned(poor);
    CHECK(w.find("known only to 1 edge +- ") != std::string::npos);
    CHECK(w.find("--startup-samples") != std::string::npos);
    CHECK(w.find("--direct-samples") != std::string::npos);

    auto cornell = loadScene(shippedScene("cornell-box"));
    cornell->camera = cornell->camera.withResolution(24, 24);
    s.direct.samples = 16;
    s.paths.maxDepth = cornell->integrator.maxDepth;
    const MltOutcome good = MltJob(*cornell, s, std::nullopt).run(RunControl(2));
    INFO(good.summary);
    CHECK(warned(good).empty());
}
