// The stratified sampler (sampling/sobol_sampler.h): Sobol's first two components are a (0, 2)-sequence,
// Owen scrambling keeps nets nets, every slot of a pixel's samples is a net, slots and pixels are
// uncorrelated, and a smooth integrand converges far faster than with independent numbers. The net
// properties are exact; the statistical checks take their bounds from the independent case's variance.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <vector>

#include "math/rng.h"
#include "sampling/sobol_sampler.h"

using namespace lt;

namespace {

// Whether the 2^m points (x, y) (32-bit fractions) form a (0, m, 2)-net in base 2: for every split
// j + k = m, each of the 2^j x 2^k elementary intervals holds exactly one point.
bool isNet(const std::vector<uint32_t>& x, const std::vector<uint32_t>& y, int m) {
    const size_t n = size_t(1) << m;
    if (x.size() != n || y.size() != n) return false;
    for (int j = 0; j <= m; ++j) {
        std::vector<int> count(n, 0);
        for (size_t i = 0; i < n; ++i) {
            const uint64_t cx = j == 0 ? 0 : x[i] >> (32 - j), cy = j == m ? 0 : y[i] >> (32 - (m - j));
            if (++count[(cx << (m - j)) | cy] > 1) return false;
        }
    }
    return true;
}

// Whether the 2^m fractions fall one in each interval [k 2^-m, (k + 1) 2^-m).
bool isStratified(const std::vector<uint32_t>& x, int m) {
    const size_t n = size_t(1) << m;
    std::vector<int> count(n, 0);
    for (const uint32_t v : x)
        if (m > 0 && ++count[v >> (32 - m)] > 1) return false;
    return x.size() == n;
}

uint32_t digits(double u) { return uint32_t(std::ldexp(u, 32)); } // the 32 leading binary digits of u in [0, 1)

double correlation(const std::vector<double>& a, const std::vector<double>& b) {
    double ma = 0, mb = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        ma += a[i] / double(a.size());
        mb += b[i] / double(b.size());
    }
    double sab = 0, saa = 0, sbb = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        sab += (a[i] - ma) * (b[i] - mb);
        saa += (a[i] - ma) * (a[i] - ma);
        sbb += (b[i] - mb) * (b[i] - mb);
    }
    return sab / std::sqrt(saa * sbb);
}

} // namespace

TEST_CASE("Sobol's first two components are a (0, 2)-sequence: every aligned block of 2^m points is a net",
          "[sampler]") {
    // The first points: 0, 1/2, 1/4, 3/4 and 0, 1/2, 3/4, 1/4 (Sobol 1967; Kollig and Keller 2002, Fig. 2).
    const uint32_t half = 1u << 31, quarter = 1u << 30;
    CHECK(sobolComponent0(0) == 0);
    CHECK(sobolComponent0(1) == half);
    CHECK(sobolComponent0(2) == quarter);
    CHECK(sobolComponent0(3) == half + quarter);
    CHECK(sobolComponent1(0) == 0);
    CHECK(sobolComponent1(1) == half);
    CHECK(sobolComponent1(2) == half + quarter);
    CHECK(sobolComponent1(3) == quarter);
    Pcg32 rng(7, 1);
    for (int m = 0; m <= 12; ++m) {
        // The first block, and blocks at random aligned offsets (the high digits a shuffle leaves constant).
        for (int b = 0; b < 4; ++b) {
            const uint32_t base = b == 0 ? 0u : (rng.nextUInt() >> m) << m;
            std::vector<uint32_t> x, y;
            for (uint32_t i = 0; i < (1u << m); ++i) {
                x.push_back(sobolComponent0(base + i));
                y.push_back(sobolComponent1(base + i));
            }
            CAPTURE(m, base);
            CHECK(isNet(x, y, m));
        }
    }
}

TEST_CASE("Owen scrambling keeps a net a net, moves its points, and shuffles indices within aligned blocks",
          "[sampler]") {
    Pcg32 rng(11, 3);
    for (int m : {1, 4, 8, 11}) {
        for (int s = 0; s < 8; ++s) {
            const uint32_t seedX = rng.nextUInt(), seedY = rng.nextUInt(), seedIndex = rng.nextUInt();
            std::vector<uint32_t> x, y, shuffled;
            int moved = 0;
            for (uint32_t i = 0; i < (1u << m); ++i) {
                x.push_back(owenScramble(sobolComponent0(i), seedX));
                y.push_back(owenScramble(sobolComponent1(i), seedY));
                moved += x.back() != sobolComponent0(i);
                shuffled.push_back(owenScramble(i, seedIndex));
            }
            CAPTURE(m, seedX, seedY);
            CHECK(isNet(x, y, m));
            // A uniform scramble leaves a given point in place with probability 2^-32.
            CHECK(moved == (1 << m));
            // The shuffled indices of a block are one aligned block: the same high digits, all low ones.
            std::vector<uint32_t> low;
            for (const uint32_t i : shuffled) {
                CHECK((i >> m) == (shuffled[0] >> m));
                low.push_back(i << (32 - m));
            }
            CHECK(isStratified(low, m));
        }
    }
}

TEST_CASE("every slot of the Sobol sampler is a net over a pixel's first 2^m samples, 1D and 2D alike", "[sampler]") {
    // A path's calls: a 2D pixel position, then per bounce a 1D light choice, a 2D light sample, a 1D lobe
    // choice and a 2D direction.
    const std::vector<int> calls = {2, 1, 2, 1, 2, 1, 2, 1, 2, 2, 1};
    for (int m : {0, 3, 8}) {
        for (uint64_t pixel : {0ull, 1ull, 12345ull}) {
            std::vector<std::vector<uint32_t>> first(calls.size()), second(calls.size());
            for (uint32_t i = 0; i < (1u << m); ++i) {
                SobolSampler s(42, pixel, i);
                for (size_t c = 0; c < calls.size(); ++c) {
                    if (calls[c] == 1) {
                        const double u = s.next1D();
                        REQUIRE((u >= 0 && u < 1));
                        first[c].push_back(digits(u));
                    } else {
                        const Vec2 u = s.next2D();
                        REQUIRE((u.x >= 0 && u.x < 1 && u.y >= 0 && u.y < 1));
                        first[c].push_back(digits(u.x));
                        second[c].push_back(digits(u.y));
                    }
                }
            }
            for (size_t c = 0; c < calls.size(); ++c) {
                CAPTURE(m, pixel, c);
                CHECK(isStratified(first[c], m));
                if (calls[c] == 2) CHECK(isNet(first[c], second[c], m));
            }
        }
    }
}

TEST_CASE("the Sobol sampler's slots and pixels are uncorrelated", "[sampler]") {
    // Over N samples the correlation of two independent uniform sequences has standard deviation 1/sqrt(N);
    // stratified ones no more. 5 standard deviations: a false failure has probability below 1e-6 per check.
    // Two slots that shared one point index (no shuffle) would be scrambles of the same point: |r| near 1
    // in their leading digits.
    const int n = 4096;
    std::vector<std::vector<double>> slot(6);
    std::vector<double> otherPixel;
    for (uint32_t i = 0; i < uint32_t(n); ++i) {
        SobolSampler s(3, 77, i);
        for (auto& v : slot)
            v.push_back(s.next1D());
        SobolSampler t(3, 78, i);
        otherPixel.push_back(t.next1D());
    }
    const double bound = 5 / std::sqrt(double(n));
    for (size_t a = 0; a < slot.size(); ++a)
        for (size_t b = a + 1; b < slot.size(); ++b) {
            CAPTURE(a, b);
            CHECK(std::abs(correlation(slot[a], slot[b])) < bound);
        }
    CHECK(std::abs(correlation(slot[0], otherPixel)) < bound);
}

TEST_CASE("a smooth integrand converges far faster with the Sobol sampler than with independent numbers", "[sampler]") {
    // f(u, v) = exp(u) v^2 over the unit square: integral (e - 1) / 3, variance under uniform sampling
    // E[f^2] - I^2 = (e^2 - 1) / 10 - I^2. With N = 256 independent samples the estimate's variance is that
    // over N; for an Owen-scrambled net and a smooth integrand it is O(N^-3 log N) (Owen 1997), here orders of
    // magnitude smaller. The check asks for a 16th of the independent variance, measured over 200 pixels (the
    // mean square error of 200 independent estimates is within 30 % of its expectation with probability
    // above 1 - 1e-6, so an unstratified sampler cannot pass).
    const double e = std::exp(1.0), integral = (e - 1) / 3, variance = (e * e - 1) / 10 - integral * integral;
    const int n = 256, pixels = 200;
    double mse = 0;
    for (int p = 0; p < pixels; ++p) {
        double sum = 0;
        for (uint32_t i = 0; i < uint32_t(n); ++i) {
            SobolSampler s(5, uint64_t(p), i);
            (void)s.next1D(); // a slot before, as in a path
            const Vec2 u = s.next2D();
            sum += std::exp(u.x) * u.y * u.y;
        }
        const double err = sum / n - integral;
        mse += err * err / pixels;
    }
    INFO("mean square error " << mse << ", independent sampling's " << variance / n);
    CHECK(mse < variance / n / 16);
}
