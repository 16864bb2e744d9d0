// The Markov-chain machinery: the primary-sample vector, the Metropolis-Hastings step with expected-value
// accumulation, and the primary-space chains against analytic answers and against BDPT. Tolerances come
// from the spread of independent chains (or runs), never from an observed value.
#include <catch2/catch.hpp>

#include <cmath>
#include <numeric>

#include "math/error.h"
#include "mcmc/metropolis.h"
#include "mcmc/mutations/bidirectional_mutation.h"
#include "mcmc/path_space_chains.h"
#include "mcmc/primary_sample_vector.h"
#include "mcmc/primary_space_chains.h"
#include "sampling/render.h"
#include "test_util.h"

using namespace lt;

namespace {

struct MeanAndError {
    double mean = 0, error = 0; // mean over runs, and its standard error
};
MeanAndError meanAndError(const std::vector<double>& v) {
    const double n = double(v.size());
    const double m = std::accumulate(v.begin(), v.end(), 0.0) / n;
    double s2 = 0;
    for (const double x : v)
        s2 += (x - m) * (x - m);
    return {m, std::sqrt(s2 / (n - 1) / n)};
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
        CHECK(std::min(d, 1 - d) <= SmallStepKernel{}.s2 + 1e-15);
        CHECK(std::min(d, 1 - d) >= SmallStepKernel{}.s1 - 1e-15);
    }
    // ... reading more camera numbers than before does not shift the light stream ...
    (void)u.next1D();
    u.startStream(SampleGenerator::LightStream);
    const double l0 = u.next1D();
    const double d = std::abs(l0 - light[0]);
    CHECK(std::min(d, 1 - d) <= SmallStepKernel{}.s2 + 1e-15);
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
        REQUIRE(std::abs(o) >= k.s1 * (1 - 1e-12));
        REQUIRE(std::abs(o) <= k.s2 * (1 + 1e-12));
        sum += o;
        sum2 += o * o;
        logSum += std::log(std::abs(o));
    }
    const double se = std::sqrt(sum2 / n / n);
    CHECK(std::abs(sum / n) < 5 * se);
    const double logRange = std::log(k.s2 / k.s1);
    const double logSe = logRange / std::sqrt(12.0 * n); // standard error of the mean of a uniform
    CHECK(std::abs(logSum / n - 0.5 * (std::log(k.s1) + std::log(k.s2))) < 5 * logSe);
}

TEST_CASE("stationarity on a tiny primary space whose dimension changes with the state", "[mcmc]") {
    // ALGORITHMS.md 10.8 with a target whose second coordinate is read only on half the space:
    // f(u) = 3 u1^2 where u0 < 1/2 (u1 read), and 1 elsewhere (u1 not read). The chain must visit
    // u0 < 1/2 half of the time and, there, u1 with density 3 u1^2: this needs the missed small steps
    // and large steps of the unread coordinate (mcmc/primary_sample_vector.h).
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

namespace {

// Image mean of a primary-space run.
double imageMean(const std::vector<float>& rgb, int channel = 0) {
    double s = 0;
    for (size_t i = size_t(channel); i < rgb.size(); i += 3)
        s += rgb[i];
    return s / double(rgb.size() / 3);
}

std::vector<float> runChains(const Scene& scene, PrimarySpace space, int maxDepth, uint64_t mutations, uint64_t seed,
                             int threads = 2, uint64_t startup = 20000) {
    SampleFilm film(scene.camera);
    PrimarySpaceSettings ps;
    ps.space = space;
    ps.bdpt.maxDepth = maxDepth;
    ps.startupSamples = startup;
    ChainRunSettings rs;
    rs.mutations = mutations;
    rs.chains = 32;
    rs.threads = threads;
    rs.seed = seed;
    const auto st = runPrimarySpaceChains(scene, ps, rs, film, {}, nullptr);
    REQUIRE(st.health.nonFinite == 0);
    REQUIRE(st.mutations == mutations);
    return film.develop();
}

// Path-space MLT with the bidirectional mutation, seeded by its own BDPT run.
std::vector<float> runPathChains(const Scene& scene, int maxDepth, uint64_t mutations, uint64_t seed, int threads = 2,
                                 uint64_t seedSamples = 20000) {
    SampleFilm film(scene.camera);
    BdptSettings b;
    b.maxDepth = maxDepth;
    const auto seeds = seedWithBdpt(scene, b, seedSamples, 1024, seed * 7919 + 1, threads, nullptr);
    const BidirectionalMutation bidir(scene, maxDepth);
    ChainRunSettings rs;
    rs.mutations = mutations;
    rs.chains = 32;
    rs.threads = threads;
    rs.seed = seed;
    const auto st = runPathSpaceChains(scene, seeds, {{&bidir, 1.0}}, rs, film, {}, nullptr);
    REQUIRE(st.health.nonFinite == 0);
    REQUIRE(st.mutations == mutations);
    return film.develop();
}

} // namespace

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

TEST_CASE("chains are bit-identical whatever the thread count", "[mcmc]") {
    test::TempDir dir;
    const auto scene = loadScene(test::furnaceBox(dir, 0.5, 3));
    for (const auto space : {PrimarySpace::Kelemen, PrimarySpace::Multiplexed})
        CHECK(runChains(*scene, space, 3, 5000, 3, 1, 2000) == runChains(*scene, space, 3, 5000, 3, 2, 2000));
    CHECK(runPathChains(*scene, 3, 5000, 3, 1, 2000) == runPathChains(*scene, 3, 5000, 3, 2, 2000));
}

TEST_CASE("bidirectional mutation: the density it samples with is the one T(x -> y) is computed from", "[mcmc]") {
    // ALGORITHMS.md 10.7: for many current paths, propose, and compare the density the proposal
    // multiplied while sampling with the one recomputed from the two paths alone; on a scene with glass
    // and mirror spheres (specular vertices in both directions) and on the diffuse cornell-box.
    for (const std::string name : {"cornell-spheres", "cornell-box"}) {
        auto scene = loadScene(name == "cornell-box" ? test::sharedScene(name) : test::shippedScene(name));
        scene->camera = scene->camera.withResolution(32, 32);
        BdptSettings b;
        b.maxDepth = 8;
        const auto seeds = seedWithBdpt(*scene, b, 20000, name == "cornell-box" ? 50 : 5000, 1, 2, nullptr);
        const BidirectionalMutation bidir(*scene, 8);
        Pcg32 rng(3, 3);
        int checked = 0, specular = 0, off = 0, dropped = 0;
        double worst = 0;
        for (size_t i = 0; i < seeds.paths.size(); ++i) {
            MarkovPath x;
            try {
                x = pathFromRecord(*scene, seeds.paths[i], i);
            } catch (const Error&) {
                continue;
            }
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
                worst = std::max(worst, mismatch);
                off += mismatch > 1e-3;
                CHECK(p.forwardQ > 0);
                CHECK(std::isfinite(p.reverseQ));
                // On diffuse paths the reverse move always exists (same range, lengths swapped); a specular
                // vertex in the old range can make it impossible (no split connects around it): a = 0.
                if (name == "cornell-box") CHECK(p.reverseQ > 0);
            }
        }
        INFO(name << ": " << checked << " proposals checked, " << specular << " specular vertices in them; " << off
                  << " densities off by more than 1e-3, the worst by " << worst << "; " << dropped << " dropped");
        CHECK(dropped < checked / 50);
        CHECK(checked > 1000);
        // Rays leave surfaces from an offset origin (scene/ray.h) and hits carry float barycentrics, so the
        // new vertex is not exactly on the sampled direction seen from the old one: on the edges of 1e-3
        // to 1e-4 where a sphere touches the floor the densities differ by up to ~20 %, elsewhere by less
        // than 1e-4 (measured: 0.5 % of the proposals beyond 1e-3). A wrong measure, transport mode or
        // factor would be off on most proposals.
        CHECK(off < checked / 100);
        CHECK(worst < 0.5);
        if (name == "cornell-spheres") CHECK(specular > 100);
    }
}

namespace {

// Every chain method against BDPT on a scene at low resolution: block means (blocks of 4 x 4 pixels, green
// channel) over independent runs of each method; each block must agree within 5 combined standard errors
// of the runs' spread.
void checkAgainstBdpt(Scene& scene, int depth, int runs, const std::vector<int>& methods) {
    const int w = 24, h = 24;
    scene.camera = scene.camera.withResolution(w, h);
    const int bs = 4, nb = (w / bs) * (h / bs);
    auto blocks = [&](const std::vector<float>& img) {
        std::vector<double> out(size_t(nb), 0.0);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                out[size_t((y / bs) * (w / bs) + x / bs)] += img[3 * size_t(y * w + x) + 1] / (bs * bs);
        return out;
    };
    auto collect = [&](auto render) {
        std::vector<std::vector<double>> perBlock(static_cast<size_t>(nb));
        for (int r = 0; r < runs; ++r) {
            const auto b = blocks(render(uint64_t(r)));
            for (int i = 0; i < nb; ++i)
                perBlock[size_t(i)].push_back(b[size_t(i)]);
        }
        std::vector<MeanAndError> out;
        for (const auto& v : perBlock)
            out.push_back(meanAndError(v));
        return out;
    };
    BdptSettings b;
    b.maxDepth = depth;
    const auto reference = collect([&](uint64_t seed) {
        SampleFilm film(scene.camera);
        RenderSettings rs;
        rs.bdpt = b;
        rs.spp = 64;
        rs.seed = 100 + seed;
        render(scene, rs, film, {}, nullptr);
        return film.develop();
    });
    for (const int method : methods) {
        const auto chains = collect([&](uint64_t seed) {
            return method == 2 ? runPathChains(scene, depth, w * h * 64, seed)
                               : runChains(scene, method == 0 ? PrimarySpace::Kelemen : PrimarySpace::Multiplexed,
                                           depth, w * h * 64, seed);
        });
        int outliers = 0;
        for (int i = 0; i < nb; ++i) {
            const double se = std::hypot(chains[size_t(i)].error, reference[size_t(i)].error);
            const double z = (chains[size_t(i)].mean - reference[size_t(i)].mean) / se;
            if (std::abs(z) > 5) {
                ++outliers;
                UNSCOPED_INFO("block " << i << ": " << chains[size_t(i)].mean << " vs BDPT "
                                       << reference[size_t(i)].mean << " (z = " << z << ")");
            }
        }
        INFO((method == 0 ? "PSSMLT" : method == 1 ? "MMLT" : "path-space MLT"));
        CHECK(outliers == 0);
    }
}

} // namespace

TEST_CASE("PSSMLT, MMLT and path-space MLT converge to BDPT on the shared cornell-box", "[mcmc][slow]") {
    auto scene = loadScene(test::sharedScene("cornell-box"));
    checkAgainstBdpt(*scene, 4, 6, {0, 1, 2});
}

TEST_CASE("path-space MLT converges to BDPT through glass and mirror spheres", "[mcmc][slow]") {
    // Specular vertices kept, deleted and re-sampled from both sides (markov_path.h's stripped deltas).
    auto scene = loadScene(test::shippedScene("cornell-spheres"));
    checkAgainstBdpt(*scene, 5, 6, {2});
}

TEST_CASE("a seed path's f / p recomputed from scratch equals the BDPT contribution it was stored with", "[mcmc]") {
    // The record of strategy (s, t) stores BDPT's unweighted f / p. Re-created from its vertices alone,
    // f~ / p~ of the same split (s light-side vertices, the rest from the eye) must give the same value
    // (times the pixel count, markov_path.h; camera strategies also by the crop-to-sensor density ratio):
    // this ties the delta stripping of specular vertices to BDPT's throughput weights.
    auto scene = loadScene(test::shippedScene("cornell-spheres"));
    scene->camera = scene->camera.withResolution(32, 32);
    BdptSettings b;
    b.maxDepth = 6;
    const auto seeds = seedWithBdpt(*scene, b, 20000, 3000, 2, 2, nullptr);
    const BidirectionalMutation bidir(*scene, 6);
    const SensorWindow sensor(scene->camera);
    const double pixels = 32 * 32;
    int checked = 0, specular = 0, bad = 0;
    for (size_t i = 0; i < seeds.paths.size(); ++i) {
        const auto& rec = seeds.paths[i];
        MarkovPath x;
        try {
            x = pathFromRecord(*scene, rec, i);
        } catch (const Error&) {
            continue;
        }
        const int k = x.edges();
        double split = 0;
        (void)bidir.newVertexDensity(x, 0, k - 1, rec.s, &split);
        // newVertexDensity's light side starts with the area-emitter choice; BDPT chooses among all.
        double areaMass = 0;
        for (size_t e = 0; e < scene->emitters.size(); ++e)
            if (scene->emitters[e]->shape >= 0) areaMass += scene->emitterSelection.pmf(e);
        if (rec.s > 0) split *= areaMass;
        const Spectrum c(rec.contribution[0], rec.contribution[1], rec.contribution[2]);
        const double expected = pixels * c.luminance() / (rec.t >= 2 ? sensor.cropToSensorDensity() : 1.0);
        if (!(split > 0) || !(expected > 0)) continue;
        ++checked;
        bool hasSpecular = false;
        for (const auto& v : x.v)
            hasSpecular |= isSpecular(v);
        specular += hasSpecular;
        const double ratio = x.target / split / expected;
        if (std::abs(ratio - 1) > 1e-3) {
            ++bad;
            UNSCOPED_INFO("path " << i << " (s = " << rec.s << ", t = " << rec.t << ", specular " << hasSpecular
                                  << "): ratio " << ratio);
        }
    }
    INFO(checked << " paths checked, " << specular << " with specular vertices");
    CHECK(checked > 1000);
    CHECK(specular > 50);
    CHECK(bad <= checked / 100);
}
