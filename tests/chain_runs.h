// Runs of the Markov chains shared by the tests that compare them with analytic answers and with BDPT:
// one primary-space or path-space run's image, and a comparison of several methods with BDPT block by
// block over independent runs. Tolerances come from the spread of independent runs.
#pragma once

#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <numeric>
#include <string>
#include <vector>

#include "mcmc/path_space_chains.h"
#include "mcmc/primary_space_chains.h"
#include "mcmc/mutation_selection.h"
#include "sampling/render.h"
#include "test_util.h"

namespace lt::test {

struct MeanAndError {
    double mean = 0, error = 0; // mean over runs, and its standard error
};
inline MeanAndError meanAndError(const std::vector<double>& v) {
    const double n = double(v.size());
    const double m = std::accumulate(v.begin(), v.end(), 0.0) / n;
    double s2 = 0;
    for (const double x : v)
        s2 += (x - m) * (x - m);
    return {m, std::sqrt(s2 / (n - 1) / n)};
}

// A shipped scene at 32 x 32 pixels and `keep` BDPT seed paths of up to `maxDepth` edges drawn from `samples`
// camera samples with seed `seed`: the states the proposal tests start from.
struct SeededScene {
    std::unique_ptr<Scene> scene;
    PathSpaceSeeds seeds;
};
inline SeededScene seededScene(const std::string& name, int maxDepth, uint64_t samples, size_t keep, uint64_t seed) {
    auto scene = loadScene(shippedScene(name));
    scene->camera = scene->camera.withResolution(32, 32);
    PathSettings b;
    b.maxDepth = maxDepth;
    auto seeds = seedWithBdpt(*scene, b, samples, keep, seed, RunControl(2));
    return {std::move(scene), std::move(seeds)};
}

// A BDPT render of the scene's film: `spp` samples per pixel with seed `seed`, paths of up to `maxDepth` edges.
inline SampleFilm bdptFilm(const Scene& scene, int maxDepth, int spp, uint64_t seed) {
    PathSettings b;
    b.maxDepth = maxDepth;
    SampleFilm film(scene.camera);
    RenderSettings rs;
    rs.paths = b;
    rs.spp = spp;
    rs.seed = seed;
    render(scene, Bdpt(scene, b), rs, film, RunControl(2));
    return film;
}

// Image mean of a primary-space run.
inline double imageMean(const std::vector<float>& rgb, int channel = 0) {
    double s = 0;
    for (size_t i = size_t(channel); i < rgb.size(); i += 3)
        s += rgb[i];
    return s / double(rgb.size() / 3);
}

inline std::vector<float> runChains(const Scene& scene, PrimarySpace space, int maxDepth, uint64_t mutations,
                                    uint64_t seed, int threads = 2, uint64_t startup = 20000) {
    SampleFilm film(scene.camera);
    PrimarySpaceSettings ps;
    ps.space = space;
    ps.paths.maxDepth = maxDepth;
    ps.startupSamples = startup;
    ChainRunSettings rs;
    rs.mutations = mutations;
    rs.chains = 128;
    rs.seed = seed;
    const auto st = runPrimarySpaceChains(scene, ps, rs, film, RunControl(threads));
    REQUIRE(st.health.nonFinite == 0);
    REQUIRE(st.mutations == mutations);
    return film.develop(st.b);
}

// Path-space MLT with a --strategies mix, seeded by its own BDPT run; `stats` (optional) accumulates
// the strategies' counters.
inline std::vector<float> runPathMix(const Scene& scene, const std::string& strategies, int maxDepth,
                                     uint64_t mutations, uint64_t seed, int threads = 2, uint64_t seedSamples = 20000,
                                     MutationStatistics* stats = nullptr) {
    SampleFilm film(scene.camera);
    PathSettings b;
    b.maxDepth = maxDepth;
    const auto seeds = seedWithBdpt(scene, b, seedSamples, 1024, seed * 7919 + 1, RunControl(threads));
    std::vector<std::unique_ptr<Mutation>> owned;
    std::vector<WeightedMutation> mix;
    makeMutations(chooseMutations(strategies, analyzeScene(scene)), {scene, maxDepth}, {}, owned, mix);
    ChainRunSettings rs;
    rs.mutations = mutations;
    rs.chains = 32;
    rs.seed = seed;
    const auto st = runPathSpaceChains(scene, seeds, mix, rs, b, 1.0 / 16, film, RunControl(threads));
    REQUIRE(st.health.nonFinite == 0);
    REQUIRE(st.mutations == mutations);
    if (stats) {
        if (stats->strategies().empty())
            *stats = st.strategies;
        else
            stats->merge(st.strategies);
    }
    return film.develop(st.b);
}

inline std::vector<float> runPathChains(const Scene& scene, int maxDepth, uint64_t mutations, uint64_t seed,
                                        int threads = 2, uint64_t seedSamples = 20000) {
    return runPathMix(scene, "bidirectional", maxDepth, mutations, seed, threads, seedSamples);
}

// Chain methods against BDPT on a scene at 24 x 24: block means (4 x 4 pixels, green channel) over
// `runs` independent runs of each. A block's z compares two means whose errors are estimated from few
// runs, so it follows roughly a Student t with about 2 (runs - 1) degrees of freedom, not a normal: for
// 6 + 6 runs P(|t| > 8) is about 1e-5 per block, so a correct method fails with probability below 1e-3
// over the blocks of all the methods tested. The real biases met while building this (specular paths
// lost, the sensor ring) gave |z| of 11 to 18. The t holds only where each run's block means are close
// to normal: BDPT runs of `bdptSpp` samples per pixel that almost never find a light smaller than a pixel,
// or chains whose visits are skewed, need more samples per run (the callers say where).
using RunRenderer = std::function<std::vector<float>(uint64_t seed)>;
inline void checkAgainstBdpt(Scene& scene, int depth, int runs,
                             const std::vector<std::pair<std::string, RunRenderer>>& methods, int bdptSpp = 64) {
    const int w = 24, h = 24;
    scene.camera = scene.camera.withResolution(w, h);
    const int bs = 4, nb = (w / bs) * (h / bs);
    auto collect = [&](const RunRenderer& render) {
        std::vector<std::vector<double>> perBlock(static_cast<size_t>(nb));
        for (int r = 0; r < runs; ++r) {
            const auto img = render(uint64_t(r));
            std::vector<double> block(size_t(nb), 0.0);
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x)
                    block[size_t((y / bs) * (w / bs) + x / bs)] += img[3 * size_t(y * w + x) + 1] / (bs * bs);
            for (int i = 0; i < nb; ++i)
                perBlock[size_t(i)].push_back(block[size_t(i)]);
        }
        std::vector<MeanAndError> out;
        for (const auto& v : perBlock)
            out.push_back(meanAndError(v));
        return out;
    };
    const auto reference =
        collect([&](uint64_t seed) { return bdptFilm(scene, depth, bdptSpp, 100 + seed).develop(); });
    for (const auto& [name, renderer] : methods) {
        const auto chains = collect(renderer);
        int outliers = 0;
        for (int i = 0; i < nb; ++i) {
            const double se = std::hypot(chains[size_t(i)].error, reference[size_t(i)].error);
            const double z = (chains[size_t(i)].mean - reference[size_t(i)].mean) / se;
            if (std::abs(z) > 8) {
                ++outliers;
                UNSCOPED_INFO("block " << i << ": " << chains[size_t(i)].mean << " vs BDPT "
                                       << reference[size_t(i)].mean << " (z = " << z << ")");
            }
        }
        INFO(name);
        CHECK(outliers == 0);
    }
}

inline RunRenderer primaryRuns(const Scene& scene, PrimarySpace space, int depth) {
    return [&scene, space, depth](uint64_t seed) { return runChains(scene, space, depth, 24 * 24 * 64, seed); };
}
inline RunRenderer pathRuns(const Scene& scene, const std::string& strategies, int depth,
                            MutationStatistics* stats = nullptr) {
    return [&scene, strategies, depth, stats](uint64_t seed) {
        return runPathMix(scene, strategies, depth, 24 * 24 * 64, seed, 2, 20000, stats);
    };
}

// What every proposal of a perturbation that went through must show: a positive sampled density, the
// configuration kept, both Q finite and the forward one positive. Returns |recomputed / sampled - 1|, the
// mismatch of the density it sampled with and the T(x -> y) it computed from the two states.
inline double proposalDensityMismatch(const Mutation& mutation, const Proposal& p) {
    REQUIRE(p.sampledDensity > 0);
    REQUIRE(mutation.suitable(p.y));
    CHECK(p.forwardQ > 0);
    CHECK(std::isfinite(p.forwardQ));
    CHECK(std::isfinite(p.reverseQ));
    return std::abs(p.recomputedDensity / p.sampledDensity - 1);
}

} // namespace lt::test
