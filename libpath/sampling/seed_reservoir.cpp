#include "sampling/seed_reservoir.h"

#include <cmath>
#include <unordered_set>

namespace lt {

SeedReservoir::SeedReservoir(size_t capacity, uint64_t seed) : slots_(capacity), rng_(seed, 0x5eed) {}

size_t SeedReservoir::binomial(size_t n, double p) {
    if (p >= 1) return n;
    if (p <= 0) return 0;
    // Inversion by sequential search (Devroye 1986, X.4): expected cost O(n p), which over a whole run
    // sums to O(K log N) since p = w / W shrinks as candidates accumulate.
    const double q = 1 - p;
    double pmf = std::exp(double(n) * std::log1p(-p));
    double u = rng_.nextDouble();
    size_t k = 0;
    while (u > pmf && k < n) {
        u -= pmf;
        pmf *= (double(n - k) / double(k + 1)) * (p / q);
        ++k;
    }
    return k;
}

void SeedReservoir::add(const file::PathRecord& rec) {
    const double w = rec.weight;
    if (!(w > 0) || !std::isfinite(w) || slots_.empty()) return;
    ++candidates_;
    total_ += w;
    const size_t m = binomial(slots_.size(), w / total_);
    if (m == 0) return;
    auto shared = std::make_shared<const file::PathRecord>(rec);
    const size_t k = slots_.size();
    if (m == k) {
        for (auto& s : slots_) s = shared;
        return;
    }
    // Floyd's algorithm: m distinct slots, uniformly.
    std::unordered_set<size_t> chosen;
    for (size_t j = k - m; j < k; ++j) {
        const size_t t = size_t(rng_.nextDouble() * double(j + 1));
        const size_t pick = chosen.count(t) ? j : t;
        chosen.insert(pick);
        slots_[pick] = shared;
    }
}

std::vector<file::PathRecord> SeedReservoir::draws() const {
    std::vector<file::PathRecord> out;
    out.reserve(slots_.size());
    for (const auto& s : slots_)
        if (s) out.push_back(*s);
    return out;
}

} // namespace lt
