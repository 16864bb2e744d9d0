#include "sampling/seed_reservoir.h"

#include <cmath>

namespace lt {

SeedReservoir::SeedReservoir(size_t capacity, uint64_t seed, int minEdges)
    : slots_(capacity), rng_(seed, 0x5eed), minEdges_(minEdges) {}

void SeedReservoir::add(const file::PathRecord& rec) {
    const double w = rec.weight;
    if (!(w > 0) || !std::isfinite(w) || slots_.empty()) return;
    if (minEdges_ > 1 && int(rec.vertices.size()) - 1 < minEdges_) return;
    ++candidates_;
    total_ += w;
    const double p = w / total_;
    std::shared_ptr<const file::PathRecord> shared;
    auto take = [&](size_t i) {
        if (!shared) shared = std::make_shared<const file::PathRecord>(rec);
        slots_[i] = shared;
    };
    if (p >= 1) {
        for (size_t i = 0; i < slots_.size(); ++i) take(i);
        return;
    }
    // Each slot switches with probability p, independently: walk the slots by geometric skips (the gap to
    // the next switching slot is Geometric(p); Devroye 1986, X.2), exact for any p and O(K p) per call,
    // so a whole run costs O(K log N) as p = w / W shrinks.
    const double logQ = std::log1p(-p);
    for (double i = -1;;) {
        const double u = 1.0 - rng_.nextDouble();   // in (0, 1]
        i += 1 + std::floor(std::log(u) / logQ);
        if (!(i < double(slots_.size()))) break;
        take(size_t(i));
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
