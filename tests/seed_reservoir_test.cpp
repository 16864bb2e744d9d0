// The seed reservoir keeps K independent draws, each proportional to weight over all candidates.
#include <catch2/catch.hpp>

#include <cmath>
#include <map>

#include "sampling/seed_reservoir.h"

using namespace lt;

namespace {

// Slots held by each candidate (identified by rngStream) after offering weights[i] for i = 0..n-1.
std::map<uint64_t, double> slotCounts(const std::vector<double>& weights, size_t k, uint64_t seed) {
    SeedReservoir r(k, seed);
    for (size_t i = 0; i < weights.size(); ++i) {
        file::PathRecord rec;
        rec.weight = weights[i];
        rec.rngStream = i;
        r.add(rec);
    }
    std::map<uint64_t, double> counts;
    for (const auto& d : r.draws()) counts[d.rngStream] += 1;
    return counts;
}

// Pearson's chi-square of slot counts against K w_i / W. With K independent draws the counts are
// multinomial: the statistic has n - 1 degrees of freedom, mean n - 1 and standard deviation
// sqrt(2 (n - 1)); 6 standard deviations bound a false failure far below 1e-6.
void checkProportional(const std::vector<double>& weights, size_t k, uint64_t seed) {
    const auto counts = slotCounts(weights, k, seed);
    double total = 0;
    for (double w : weights) total += w;
    double chi2 = 0;
    for (size_t i = 0; i < weights.size(); ++i) {
        const double expected = double(k) * weights[i] / total;
        const double got = counts.count(i) ? counts.at(i) : 0.0;
        chi2 += (got - expected) * (got - expected) / expected;
    }
    const double dof = double(weights.size() - 1);
    CHECK(chi2 < dof + 6 * std::sqrt(2 * dof));
}

} // namespace

TEST_CASE("seed reservoir: equal weights are kept uniformly", "[seeds]") {
    checkProportional(std::vector<double>(1000, 1.0), 100000, 1);
}

TEST_CASE("seed reservoir: unequal weights are kept in proportion", "[seeds]") {
    std::vector<double> w;
    for (int i = 1; i <= 300; ++i) w.push_back(i * 0.01 + (i % 7 == 0 ? 3.0 : 0.0));
    checkProportional(w, 60000, 2);
}

TEST_CASE("seed reservoir: a heavy candidate takes its share, not every slot", "[seeds]") {
    // Candidate 500 carries 2 % of the total weight: Binomial(K, 0.02) slots, sd sqrt(K 0.02 0.98).
    std::vector<double> w(1000, 1.0);
    w[500] = 0.02 / 0.98 * 999;
    const size_t k = 100000;
    const auto counts = slotCounts(w, k, 3);
    const double sd = std::sqrt(double(k) * 0.02 * 0.98);
    CHECK(std::abs(counts.at(500) - 0.02 * double(k)) < 6 * sd);
}

TEST_CASE("seed reservoir: zero and non-finite weights are not candidates", "[seeds]") {
    SeedReservoir r(10, 4);
    file::PathRecord rec;
    rec.weight = 0;
    r.add(rec);
    rec.weight = NAN;
    r.add(rec);
    CHECK(r.candidates() == 0);
    CHECK(r.draws().empty());
    rec.weight = 2;
    r.add(rec);
    CHECK(r.draws().size() == 10);
    CHECK(r.totalWeight() == 2);
}
