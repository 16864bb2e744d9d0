#include "mcmc/mutation_statistics.h"

#include <cstdio>

namespace lt {

const char* rejectCauseName(RejectCause c) {
    switch (c) {
    case RejectCause::ZeroContribution:
        return "zero_contribution";
    case RejectCause::Occluded:
        return "occluded";
    case RejectCause::LeftImage:
        return "left_image";
    case RejectCause::ConfigurationChanged:
        return "configuration_changed";
    case RejectCause::NonFinite:
        return "nonfinite";
    case RejectCause::WalkFailed:
        return "walk_failed";
    case RejectCause::NotReversible:
        return "not_reversible";
    case RejectCause::Missed:
        return "missed";
    case RejectCause::Count:
        break;
    }
    return "?";
}

void StrategyCounters::merge(const StrategyCounters& o) {
    proposed += o.proposed;
    accepted += o.accepted;
    acceptance += o.acceptance;
    for (size_t i = 0; i < rejected.size(); ++i)
        rejected[i] += o.rejected[i];
    seconds += o.seconds;
}

MutationStatistics::MutationStatistics(std::vector<std::string> strategies,
                                       std::vector<std::unique_ptr<MutationFigures>> figures)
    : names_(std::move(strategies)), counters_(names_.size()), figures_(std::move(figures)) {
    figures_.resize(names_.size());
}

MutationStatistics::MutationStatistics(const MutationStatistics& o) { *this = o; }

MutationStatistics& MutationStatistics::operator=(const MutationStatistics& o) {
    if (this == &o) return *this;
    names_ = o.names_;
    counters_ = o.counters_;
    figures_.clear();
    for (const auto& f : o.figures_)
        figures_.push_back(f ? f->clone() : nullptr);
    return *this;
}

void MutationStatistics::merge(const MutationStatistics& o) {
    for (size_t i = 0; i < counters_.size() && i < o.counters_.size(); ++i) {
        counters_[i].merge(o.counters_[i]);
        if (figures_[i] && o.figures_[i]) figures_[i]->merge(*o.figures_[i]);
    }
}

file::StatTable MutationStatistics::table(const std::string& name) const {
    file::StatTable t;
    t.name = name;
    t.columns = {"proposed", "accepted", "acceptance"};
    for (int c = 0; c < int(RejectCause::Count); ++c)
        t.columns.push_back(rejectCauseName(RejectCause(c)));
    t.columns.push_back("seconds");
    t.rows = names_;
    for (const auto& k : counters_) {
        std::vector<double> row = {double(k.proposed), double(k.accepted),
                                   k.proposed ? k.acceptance / double(k.proposed) : 0.0};
        for (const auto r : k.rejected)
            row.push_back(double(r));
        row.push_back(k.seconds);
        t.values.push_back(std::move(row));
    }
    return t;
}

std::vector<file::StatTable> MutationStatistics::figureTables() const {
    std::vector<file::StatTable> out;
    for (size_t i = 0; i < names_.size(); ++i)
        if (figures_[i])
            for (auto& t : figures_[i]->tables(names_[i]))
                out.push_back(std::move(t));
    return out;
}

std::string MutationStatistics::text() const {
    // The causes few strategies meet (manifold walks, portal moves) get a column only when some proposal met them.
    struct Column {
        RejectCause cause;
        const char* title;
    };
    std::vector<Column> extra;
    for (const Column c : {Column{RejectCause::WalkFailed, "walk failed"},
                           Column{RejectCause::NotReversible, "not reversible"}, Column{RejectCause::Missed, "missed"}})
        for (const auto& k : counters_)
            if (k.rejected[size_t(c.cause)]) {
                extra.push_back(c);
                break;
            }
    std::string out;
    char line[320];
    std::snprintf(line, sizeof line, "%-16s %12s %9s %10s %10s %9s %9s %9s %9s", "strategy", "proposed", "accepted",
                  "mean a", "zero f", "occluded", "off image", "config", "nonfinite");
    out += line;
    for (const auto& c : extra) {
        std::snprintf(line, sizeof line, " %14s", c.title);
        out += line;
    }
    out += "   us/prop\n";
    for (size_t i = 0; i < names_.size(); ++i) {
        const auto& k = counters_[i];
        const double n = double(k.proposed);
        auto pct = [&](RejectCause c) { return n > 0 ? 100.0 * double(k.rejected[size_t(c)]) / n : 0.0; };
        std::snprintf(line, sizeof line, "%-16s %12llu %8.2f%% %10.4f %9.2f%% %8.2f%% %8.2f%% %8.2f%% %9llu",
                      names_[i].c_str(), (unsigned long long)k.proposed, n > 0 ? 100.0 * double(k.accepted) / n : 0.0,
                      n > 0 ? k.acceptance / n : 0.0, pct(RejectCause::ZeroContribution), pct(RejectCause::Occluded),
                      pct(RejectCause::LeftImage), pct(RejectCause::ConfigurationChanged),
                      (unsigned long long)k.rejected[size_t(RejectCause::NonFinite)]);
        out += line;
        for (const auto& c : extra) {
            std::snprintf(line, sizeof line, " %13.2f%%", pct(c.cause));
            out += line;
        }
        std::snprintf(line, sizeof line, " %9.2f\n", n > 0 ? 1e6 * k.seconds / n : 0.0);
        out += line;
    }
    for (size_t i = 0; i < names_.size(); ++i)
        if (figures_[i]) out += figures_[i]->text(names_[i]);
    return out;
}

} // namespace lt
