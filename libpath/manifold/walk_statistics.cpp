#include "manifold/walk_statistics.h"

#include <algorithm>
#include <iomanip>
#include <string>

namespace lt {

void WalkStatistics::add(const WalkOutcome& w) {
    ++attempted;
    ++byCause[size_t(w.failure)];
    ++chainLengths[w.chainLength];
    iterationsAll += uint64_t(w.iterations);
    if (w.fromEye) ++(*w.fromEye ? fromEye : fromLight);
    jumpsTried += w.jump != JumpOutcome::None;
    jumpsProposed += w.jump == JumpOutcome::Proposed;
    if (w.failure == WalkFailure::None) {
        ++converged;
        iterationsConverged += uint64_t(w.iterations);
        maxIterations = std::max(maxIterations, w.iterations);
    }
}

void WalkStatistics::addAcceptance(const WalkOutcome& w, double a) {
    acceptanceByLength[w.chainLength] += a;
    if (w.jump == JumpOutcome::Proposed) jumpAcceptance += a;
}

file::StatTable WalkStatistics::table(const std::string& name, const std::string& row) const {
    file::StatTable t;
    t.name = name;
    t.columns = {"attempted",           "converged",          "mean_iterations",      "max_iterations",
                 "mean_iterations_all", "projected_from_eye", "projected_from_light", "jumps_tried",
                 "jumps_proposed",      "jump_acceptance"};
    std::vector<double> values = {
        double(attempted),        double(converged),
        double(meanIterations()), double(maxIterations),
        meanIterationsAll(),      double(fromEye),
        double(fromLight),        double(jumpsTried),
        double(jumpsProposed),    jumpsProposed ? jumpAcceptance / double(jumpsProposed) : 0.0};
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
    iterationsAll += o.iterationsAll;
    fromEye += o.fromEye;
    fromLight += o.fromLight;
    jumpsTried += o.jumpsTried;
    jumpsProposed += o.jumpsProposed;
    jumpAcceptance += o.jumpAcceptance;
    maxIterations = std::max(maxIterations, o.maxIterations);
    for (size_t i = 0; i < byCause.size(); ++i)
        byCause[i] += o.byCause[i];
    for (const auto& [len, n] : o.chainLengths)
        chainLengths[len] += n;
    for (const auto& [len, a] : o.acceptanceByLength)
        acceptanceByLength[len] += a;
}

void WalkStatistics::print(std::ostream& out) const {
    const auto pct = [&](uint64_t n) { return attempted ? 100.0 * double(n) / double(attempted) : 0.0; };
    const auto flags = out.flags();
    out << std::fixed << std::setprecision(1);
    out << "  " << std::left << std::setw(36) << "walks attempted" << attempted << "\n";
    out << "  " << std::setw(36) << "converged" << converged << " (" << pct(converged) << " %)\n";
    out << std::setprecision(2);
    out << "  " << std::setw(36) << "iterations (converged)"
        << "mean " << meanIterations() << ", max " << maxIterations << "; per walk " << meanIterationsAll() << "\n";
    if (fromEye + fromLight)
        out << "  " << std::setw(36) << "projected from the eye / light" << fromEye << " / " << fromLight << "\n";
    if (jumpsTried)
        out << "  " << std::setw(36) << "jumps tried / proposed" << jumpsTried << " / " << jumpsProposed << " ("
            << 100.0 * double(jumpsProposed) / double(jumpsTried) << " %), mean acceptance "
            << (jumpsProposed ? 100 * jumpAcceptance / double(jumpsProposed) : 0.0) << " %\n";
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
    if (!acceptanceByLength.empty()) {
        out << "  " << std::setw(36) << "acceptance by chain length";
        first = true;
        for (const auto& [len, a] : acceptanceByLength) {
            const auto it = chainLengths.find(len);
            const double n = it == chainLengths.end() ? 0.0 : double(it->second);
            out << (first ? "" : ", ") << len << ": " << (n > 0 ? 100 * a / n : 0.0) << " %";
            first = false;
        }
        out << "\n";
    }
    out.flags(flags);
}

} // namespace lt
