#include "manifold/walk_statistics.h"

#include <algorithm>
#include <iomanip>
#include <string>

namespace lt {

void WalkStatistics::add(const WalkResult& r, size_t chainLength) {
    ++attempted;
    ++byCause[size_t(r.failure)];
    ++chainLengths[chainLength];
    if (r.converged()) {
        ++converged;
        iterationsConverged += uint64_t(r.iterations);
        maxIterations = std::max(maxIterations, r.iterations);
    }
}

void WalkStatistics::merge(const WalkStatistics& o) {
    attempted += o.attempted;
    converged += o.converged;
    iterationsConverged += o.iterationsConverged;
    maxIterations = std::max(maxIterations, o.maxIterations);
    for (size_t i = 0; i < byCause.size(); ++i)
        byCause[i] += o.byCause[i];
    for (const auto& [len, n] : o.chainLengths)
        chainLengths[len] += n;
}

void WalkStatistics::print(std::ostream& out) const {
    const auto pct = [&](uint64_t n) { return attempted ? 100.0 * double(n) / double(attempted) : 0.0; };
    const auto flags = out.flags();
    out << std::fixed << std::setprecision(1);
    out << "  " << std::left << std::setw(36) << "walks attempted" << attempted << "\n";
    out << "  " << std::setw(36) << "converged" << converged << " (" << pct(converged) << " %)\n";
    out << std::setprecision(2);
    out << "  " << std::setw(36) << "iterations (converged)"
        << "mean " << meanIterations() << ", max " << maxIterations << "\n";
    out << std::setprecision(1);
    for (size_t i = 1; i < byCause.size(); ++i)
        if (byCause[i])
            out << "  " << std::setw(36) << ("failed: " + std::string(walkFailureName(WalkFailure(i)))) << byCause[i]
                << " (" << pct(byCause[i]) << " %)\n";
    out << "  " << std::setw(36) << "chain lengths (vertices)";
    bool first = true;
    for (const auto& [len, n] : chainLengths) {
        out << (first ? "" : ", ") << len << ": " << n;
        first = false;
    }
    out << "\n";
    out.flags(flags);
}

} // namespace lt
