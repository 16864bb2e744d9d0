// The manifold perturbation (Jakob & Marschner 2012, Sec. 5.1): its von Mises-Fisher direction kernel, and
// its proposals on public scenes with specular chains (the density it samples with is the T it computes;
// walks that converge come back). Its stationarity is tested with the other mutations'
// (mcmc_stationarity_test.cpp), its images against BDPT in mcmc_test.cpp.
#include <catch2/catch.hpp>

#include <cmath>
#include <sstream>
#include <vector>

#include "util/error.h"
#include "math/rng.h"
#include "manifold/chains_in_path.h"
#include "math/von_mises_fisher.h"
#include "mcmc/mutations/manifold_perturbation.h"
#include "mcmc/path_space_chains.h"
#include "chain_runs.h"
#include "test_util.h"

using namespace lt;

TEST_CASE("von Mises-Fisher: the peak is the one asked for, sampling follows the density, huge kappa stays finite",
          "[manifold]") {
    for (const double peak : {0.01, 1 / (4 * Pi) * 1.001, 0.2, 1.0, 8.0, 1e3, 1e7, 1e12, 1e200}) {
        const auto lobe = VonMisesFisher::withPeak(peak);
        INFO("peak " << peak << ", kappa " << lobe.kappa);
        const Vec3 mu = normalize(Vec3(0.3, -0.2, 0.9));
        const double at = lobe.density(mu, mu);
        REQUIRE(std::isfinite(at));
        CHECK(at == Approx(std::max(peak, 1 / (4 * Pi))).epsilon(1e-9));
    }
    // Chi-square of 64 x 8 cells in (u, phi), u = P(1 - cos theta <= s) under the kernel's own inverse CDF
    // (equal expected counts when sample() and density() agree): the expected count of each cell is N
    // times the integral of density() over the cell's solid angle.
    for (const double kappa : {0.0, 1e-3, 1.0, 50.0, 1e6, 1e10}) {
        INFO("kappa " << kappa);
        const VonMisesFisher lobe{kappa};
        const Vec3 mu = normalize(Vec3(-0.5, 0.1, -0.3));
        const Frame frame = Frame::fromNormal(mu);
        constexpr int U = 64, Phi = 8, N = 200000;
        const auto oneMinusCosOf = [&](double u) {
            return kappa > 0 ? std::min(2.0, -std::log1p(-u * -std::expm1(-2 * kappa)) / kappa) : 2 * u;
        };
        const auto direction = [&](double oneMinusCos, double phi) {
            const double s = std::sqrt(std::max(0.0, oneMinusCos * (2 - oneMinusCos)));
            return frame.toWorld(Vec3(s * std::cos(phi), s * std::sin(phi), 1 - oneMinusCos));
        };
        std::vector<double> counts(U * Phi, 0.0), expected(U * Phi, 0.0);
        Pcg32 rng(5, 11);
        for (int i = 0; i < N; ++i) {
            const Vec3 w = lobe.sample(mu, rng.nextDouble(), rng.nextDouble());
            REQUIRE(std::abs(length(w) - 1) < 1e-12);
            const Vec3 l = frame.toLocal(w);
            const Vec3 d = w - mu;
            const double oneMinusCos = 0.5 * dot(d, d);
            const double u = kappa > 0 ? -std::expm1(-kappa * oneMinusCos) / -std::expm1(-2 * kappa) : oneMinusCos / 2;
            const double phi = std::atan2(l.y, l.x) + Pi;
            counts[size_t(std::min(U - 1, int(u * U)) * Phi + std::min(Phi - 1, int(phi / (2 * Pi) * Phi)))] += 1;
        }
        for (int iu = 0; iu < U; ++iu) {
            // Midpoint rule in t = e^{-kappa (1 - cos theta)}, where d omega = 2 pi dt / (kappa t) per
            // unit azimuth fraction: the integrand density / (kappa t) is constant for a true vMF density,
            // so any error of density() shows and none of the rule's.
            const double a = oneMinusCosOf(double(iu) / U), b = oneMinusCosOf(double(iu + 1) / U);
            constexpr int Steps = 64;
            double integral = 0;
            if (kappa > 0) {
                const double ta = std::exp(-kappa * a), tb = std::exp(-kappa * b);
                for (int j = 0; j < Steps; ++j) {
                    const double t = ta + (tb - ta) * (j + 0.5) / Steps;
                    integral += lobe.density(mu, direction(std::min(2.0, -std::log(t) / kappa), 0.3)) / (kappa * t);
                }
                integral *= (ta - tb) / Steps;
            } else {
                for (int j = 0; j < Steps; ++j)
                    integral += lobe.density(mu, direction(a + (b - a) * (j + 0.5) / Steps, 0.3));
                integral *= (b - a) / Steps;
            }
            integral *= 2 * Pi / Phi;
            for (int ip = 0; ip < Phi; ++ip)
                expected[size_t(iu * Phi + ip)] = N * integral;
        }
        double chi2 = 0, total = 0;
        for (size_t c = 0; c < counts.size(); ++c) {
            total += expected[c];
            chi2 += (counts[c] - expected[c]) * (counts[c] - expected[c]) / expected[c];
        }
        CHECK(total == Approx(N).epsilon(1e-6)); // density() integrates to 1
        // Wilson-Hilferty: (chi2 / k)^(1/3) is about normal; |z| < 5 fails a correct kernel with
        // probability 6e-7.
        const double k = double(counts.size() - 1);
        const double z = (std::cbrt(chi2 / k) - (1 - 2 / (9 * k))) / std::sqrt(2 / (9 * k));
        INFO("chi2 " << chi2 << " over " << k << " degrees of freedom, z " << z);
        CHECK(std::abs(z) < 5);
    }
}

namespace {

std::vector<MarkovPath> seedStates(const Scene& scene, int depth, size_t samples, size_t paths) {
    PathSettings b;
    b.maxDepth = depth;
    const auto seeds = seedWithBdpt(scene, b, samples, paths, 1, RunControl(2));
    std::vector<MarkovPath> out;
    for (size_t i = 0; i < seeds.paths.size(); ++i) {
        try {
            out.push_back(pathFromRecord(scene, seeds.paths[i], i));
        } catch (const Error&) {
        }
    }
    return out;
}

} // namespace

TEST_CASE("manifold perturbation: the density sampled is the T(x -> y) computed, and walks come back",
          "[manifold][mcmc]") {
    // From seed paths through the glass and mirror spheres, the veach-bidir egg and the spheres under a sky
    // and a sun (chains walked with the direction of a light at infinity held), propose: the density
    // multiplied while tracing (the turned direction, the specular vertices after it) times the walked
    // chain's factor must be the T recomputed from the two states, both Q finite, and T(y -> x) the
    // one rebuilt through the public pieces (the same stages, y's kernel). A turned chain through held
    // glossy vertices has no step-by-step density (its sampled density is the closed form itself), so for
    // those proposals only the walk figures are checked here; the glossy stationarity test carries their
    // density. Of the walks that converge, fewer than 1 % may fail to come back (ME Sec. 5.1 reports
    // 0 - 0.4 %).
    int walked = 0, notReversible = 0, glossyWalks = 0, glossyNotReversible = 0;
    for (const char* name : {"cornell-spheres", "veach-bidir", "sun-caustic"}) {
        INFO(name);
        auto scene = loadScene(test::shippedScene(name));
        scene->camera = scene->camera.withResolution(32, 32);
        const auto paths = seedStates(*scene, 8, 40000, 6000);
        const ManifoldPerturbation mutation(*scene);
        Pcg32 rng(3, 9);
        int suitable = 0, checked = 0, off = 0, walkFailed = 0, balanceOff = 0, eyeSideChains = 0, eyeSideOff = 0,
            unstaged = 0, heldAtInfinity = 0;
        double worst = 0;
        for (const auto& x : paths) {
            if (!mutation.suitable(x)) continue;
            ++suitable;
            for (int j = 0; j < 10; ++j) {
                Pcg32 copy = rng;
                const auto stages = mutation.chooseStages(x, copy);
                Proposal p;
                mutation.propose(x, rng, p);
                if (!stages) { // a glossy vertex treated as specular left x_b on the path's end
                    CHECK(p.failed == RejectCause::ConfigurationChanged);
                    ++unstaged;
                    continue;
                }
                const bool walks = std::abs(stages->c - stages->b) > 1;
                bool holds = false; // a glossy vertex treated as specular in the walked chain
                for (int i = std::min(stages->b, stages->c) + 1; i < std::max(stages->b, stages->c); ++i)
                    holds |= !isSpecular(x.v[size_t(i)]);
                glossyWalks += walks && holds && (!p.failed || *p.failed == RejectCause::NotReversible);
                glossyNotReversible += holds && p.failed && *p.failed == RejectCause::NotReversible;
                if (p.failed) {
                    notReversible += walks && *p.failed == RejectCause::NotReversible;
                    walkFailed += walks && *p.failed == RejectCause::WalkFailed;
                    walked += walks && *p.failed == RejectCause::NotReversible;
                    continue;
                }
                ++checked;
                walked += walks;
                heldAtInfinity += walks && stages->c == 0 && x.v[0].infinite;
                const double mismatch = test::proposalDensityMismatch(mutation, p);
                worst = std::max(worst, mismatch);
                off += mismatch > 1e-3;
                // A chain walked with its eye end x_c held, where x_c has a surface: its light-to-eye G
                // rebuilt with the light end x_b held instead must give the same factor (the perturbation
                // turns the eye-held G into it with the R_imp / R_rad ratios of markov_path.h).
                if (walks && !holds && stages->c > stages->b && stages->c < p.y.edges()) {
                    const double lightHeld = mutation.deltaRunFactor(p.y, stages->b, stages->c);
                    if (lightHeld > 0) {
                        ++eyeSideChains;
                        eyeSideOff +=
                            !(std::abs(mutation.deltaRunFactor(p.y, stages->c, stages->b) / lightHeld - 1) < 1e-4);
                    }
                }
                const double reverseT = mutation.transitionDensity(p.y, x, *stages);
                if (reverseT > 0 || p.reverseQ > 0)
                    balanceOff += !(std::abs(reverseT / (p.reverseQ * x.target) - 1) < 1e-9);
            }
        }
        INFO(suitable << " suitable seed paths, " << checked << " proposals checked, " << unstaged
                      << " without stages; " << walked << " walks converged so far, " << walkFailed << " walks failed, "
                      << notReversible << " not reversible; " << off
                      << " densities off by more than 1e-3, the worst by " << worst);
        CHECK(checked > 1000);
        CHECK(off < checked / 100 + 1);
        CHECK(balanceOff == 0);
        INFO(heldAtInfinity << " walks with the light's direction held");
        if (std::string(name) == "sun-caustic") CHECK(heldAtInfinity > 500);
        INFO(eyeSideChains << " chains walked with a surface at their eye end, " << eyeSideOff
                           << " of them with another factor held at the light end");
        CHECK(eyeSideOff <= eyeSideChains / 100);
    }
    INFO(walked << " walks converged, " << notReversible << " of them not reversible; " << glossyWalks
                << " through held glossy vertices, " << glossyNotReversible << " of them not reversible");
    CHECK(walked > 2000);
    // Chains of delta vertices come back (ME: 0 - 0.4 % do not). Walks through held glossy vertices on
    // veach-bidir's curved lamp shade come back less often (measured: 36 of 197 beyond 1e-4 of the
    // diagonal, 27 beyond 1e-3): the check rejects those; their rate is reported, not bounded.
    CHECK(notReversible - glossyNotReversible < (walked - glossyWalks) / 100);
    CHECK(glossyWalks > 100);
}

TEST_CASE("MEMLT and HSLT on stiff cases: index nearly matched and 4, scene scales 1e-3 and 1e5, grazing view, "
          "glossy glass of roughness 1e-4 to 0.5",
          "[manifold][hslt][mcmc][long]") {
    // No NaN or Inf reaches the image, the perturbation or mutation moves the chains, and its walk figures
    // add up. With alpha 1e-4 HSLT's steps go to 1e-5 (gamma alpha / sqrt 2) and its walk tolerance with them.
    struct Case {
        double ior, scale, eyeHeight, alpha = 0;
    };
    for (const char* mix : {"bidirectional,manifold", "bidirectional,hslt"})
        for (const Case c : {Case{1.0001, 1, 1}, Case{4, 1, 1}, Case{1.5, 1e-3, 1}, Case{1.5, 1e5, 1},
                             Case{1.5, 1, 0.01}, Case{1.5, 1, 1, 1e-4}, Case{1.5, 1, 1, 0.01}, Case{1.5, 1, 1, 0.1},
                             Case{1.5, 1, 1, 0.5}, Case{1.5, 1, 0.01, 0.01}}) {
            INFO(mix << ": ior " << c.ior << ", scale " << c.scale << ", eye height " << c.eyeHeight << ", alpha "
                     << c.alpha);
            test::TempDir dir;
            const auto scene = loadScene(test::ballScene(dir, c.ior, c.scale, c.eyeHeight, c.alpha));
            MutationStatistics stats;
            const auto image = test::runPathMix(*scene, mix, 6, 200000, 3, 2, 20000, &stats);
            for (const float v : image)
                REQUIRE(std::isfinite(v));
            const auto& m = stats[1];
            INFO(stats.text());
            CHECK(m.accepted > m.proposed / 10);
            uint64_t rejected = 0;
            for (const auto r : m.rejected)
                rejected += r;
            CHECK(rejected <= m.proposed - m.accepted);
            CHECK(m.rejected[size_t(RejectCause::NonFinite)] == 0);
            const auto& w = walksOf(stats, 1);
            uint64_t failed = 0;
            for (size_t i = 1; i < w.byCause.size(); ++i)
                failed += w.byCause[i];
            CHECK(w.attempted == w.converged + failed);
            CHECK(w.converged > 0);
            // HSLT's walks each chose a projection order (all but those whose state had no chart).
            if (w.fromEye + w.fromLight > 0)
                CHECK(w.fromEye + w.fromLight == w.attempted - w.byCause[size_t(WalkFailure::Singular)]);
        }
}

TEST_CASE("MEMLT and HSLT in the furnace box with a mirror ball and a glass ball: every pixel is Le / (1 - rho)",
          "[manifold][hslt][mcmc][long]") {
    // Lossless specular balls in a furnace whose walls emit 1 and reflect rho: the radiance is 1 / (1 - rho)
    // everywhere, seen directly, in the mirror or through the glass. The chains' image mean must be it
    // (paths beyond 12 edges are cut: with rho 0.2 and balls that lose nothing, under 1e-3 of it). Every
    // path through a ball has specular vertices: HSLT holds their half vectors at 0 and turns their deltas
    // into half-vector measure (|det C| / G, half_vector_mutation.h).
    test::TempDir dir;
    const double rho = 0.2;
    const auto scene = loadScene(test::furnaceBox(dir, rho, 12, "box", 1, R"(
  <shape type="sphere"><point name="center" x="0.3" y="0.2" z="-0.6"/><float name="radius" value="0.25"/>
    <bsdf type="conductor"><string name="material" value="none"/></bsdf></shape>
  <shape type="sphere"><point name="center" x="-0.2" y="0.3" z="-0.7"/><float name="radius" value="0.2"/>
    <bsdf type="dielectric"/></shape>)"));
    const double exact = 1 / (1 - rho);
    for (const char* mix : {"bidirectional,manifold", "bidirectional,hslt:3"}) {
        std::vector<double> means;
        MutationStatistics stats;
        for (uint64_t seed = 0; seed < 8; ++seed) {
            const auto image = test::runPathMix(*scene, mix, 12, 24 * 24 * 32, seed, 2, 20000, &stats);
            means.push_back(test::imageMean(image));
        }
        const auto m = test::meanAndError(means);
        INFO(mix << ": " << m.mean << " +- " << m.error << ", exact " << exact << "\n" << stats.text());
        CHECK(std::abs(m.mean - exact) < 5 * m.error + 1e-3 * exact);
        CHECK(m.error < 0.02 * exact);
        CHECK(walksOf(stats, 1).converged > 100);
        CHECK(stats[1].accepted > stats[1].proposed / 4);
    }
}
