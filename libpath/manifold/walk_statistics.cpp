#include "manifold/walk_statistics.h"

#include <algorithm>
#include <iomanip>
#include <string>

namespace lt {

void WalkStatistics::add(const WalkOutcome& w) {
    ++attempted;
    ++byCause[size_t(w.failure)];
    ++chainLengths[w.chainLength];
    if (w.failure == WalkFailure::None) {
        ++converged;
        iterationsConverged += uint64_t(w.iterations);
        maxIterations = std::max(maxIterations, w.iterations);
    }
}

file::StatTable WalkStatistics::table(const std::string& name, const std::string& row) const {
    file::StatTable t;
    t.name = name;
    t.columns = {"attempted", "converged", "mean_iterations", "max_iterations"};
    std::vector<double> values = {double(attempted), double(converged), meanIterations(), double(maxIterations)};
    for (size_t i = 1; i < byCause.size(); ++i) {
        // A column name without blanks: "left the surface / missed" -> "failed_left_the_surface".
        std::string cause(walkFailureName(WalkFailure(i)));
        cause = cause.substr(0, cause.find(" /"));
        std::replace(cause.begin(), cause.end(), ' ', '_');
        t.columns.push_back("failed_" + cause);
        values.push_back(double(byCause[i]));
    }
    t.rows = {row};
    t.values = {values};
    return t;
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
