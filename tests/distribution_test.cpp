// Systematic resampling draws every index in proportion to its weight, up to one draw, in one pass.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include "math/distribution.h"
#include "util/error.h"
#include "math/rng.h"

using namespace lt;

TEST_CASE("systematic resampling: each index floor or ceil of n w / W times, the draws of the inverted CDF", "[math]") {
    Pcg32 rng(7, 1);
    std::vector<double> weights(5000);
    for (size_t i = 0; i < weights.size(); ++i)
        // A fifth of the weights 0, the others spread over six orders of magnitude.
        weights[i] = i % 5 == 0 ? 0.0 : std::pow(10.0, 6 * rng.nextDouble());
    double total = 0;
    for (double w : weights)
        total += w;
    const DiscreteDistribution inverse(weights);
    for (const size_t n : {size_t(1), size_t(7), size_t(256), size_t(100000)})
        for (const double offset : {0.0, 0.37, std::nextafter(1.0, 0.0)}) {
            const std::vector<size_t> draws = systematicResample(weights, n, offset);
            REQUIRE(draws.size() == n);
            CHECK(std::is_sorted(draws.begin(), draws.end()));
            std::vector<size_t> count(weights.size(), 0);
            size_t differing = 0;
            for (size_t j = 0; j < n; ++j) {
                ++count[draws[j]];
                // The same positions through the normalized CDF, rounded alike.
                differing += draws[j] != inverse.sample((double(j) + offset) / double(n));
            }
            CHECK(differing == 0);
            for (size_t i = 0; i < weights.size(); ++i) {
                // Positions 1 / n apart: a bin of width n w / W holds floor or ceil of it (a relative 1e-9 for
                // the rounding of the running sum).
                const double expected = double(n) * weights[i] / total;
                INFO("n " << n << " offset " << offset << " index " << i << " weight " << weights[i]);
                CHECK(double(count[i]) >= std::floor(expected * (1 - 1e-9)));
                CHECK(double(count[i]) <= std::ceil(expected * (1 + 1e-9)));
                if (weights[i] == 0) CHECK(count[i] == 0);
            }
        }
}

TEST_CASE("systematic resampling: zero weights at either end are never drawn, bad weights refused", "[math]") {
    // Positions near the end of the CDF, where the running sum's rounding can leave them past the total.
    const std::vector<double> weights = {0.0, 0.0, 0.1, 0.2, 0.3, 0.0, 0.0};
    for (const double offset : {0.0, 0.5, std::nextafter(1.0, 0.0)})
        for (const size_t d : systematicResample(weights, 1000, offset))
            CHECK((d >= 2 && d <= 4));
    CHECK(systematicResample(std::vector<double>{0.0, 3.0}, 4, 0.99) == std::vector<size_t>(4, 1));
    // Equal weights put positions exactly on bin edges, where the normalized CDF's rounding decides (10
    // weights of 0.3, offset 0: comparing the unnormalized sums with the position drew index 2 for j = 3,
    // the normalized CDF draws 3).
    const std::vector<double> equal(10, 0.3);
    const DiscreteDistribution inverse(equal);
    for (const double offset : {0.0, 0.5})
        for (const size_t n : {size_t(10), size_t(20), size_t(30)}) {
            const std::vector<size_t> draws = systematicResample(equal, n, offset);
            for (size_t j = 0; j < n; ++j)
                CHECK(draws[j] == inverse.sample((double(j) + offset) / double(n)));
        }
    CHECK_THROWS_AS(systematicResample(std::vector<double>{0.0, 0.0}, 4, 0.5), Error);
    CHECK_THROWS_AS(systematicResample(std::vector<double>{1.0, -1.0}, 4, 0.5), Error);
    CHECK_THROWS_AS(systematicResample(std::vector<double>{1.0, std::nan("")}, 4, 0.5), Error);
    CHECK_THROWS_AS(
        systematicResample(std::vector<double>{std::numeric_limits<double>::max(), std::numeric_limits<double>::max()},
                           4, 0.5),
        Error);
}
