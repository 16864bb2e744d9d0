// The figures of the mutations that walk a manifold (the manifold perturbation, HSLT's half-vector mutation): each
// proposal's walk (manifold/walk_statistics.h), counted with the acceptance of the proposal that made it.
#pragma once

#include <optional>

#include "manifold/walk_statistics.h"
#include "mcmc/mutation.h"

namespace lt {

class WalkFigures final : public MutationFigures {
public:
    void settle(double a) override {
        if (!walk) return;
        walks.add(*walk);
        walks.addAcceptance(*walk, a);
        walk.reset();
    }
    void merge(const MutationFigures& other) override { walks.merge(static_cast<const WalkFigures&>(other).walks); }
    [[nodiscard]] std::unique_ptr<MutationFigures> clone() const override {
        return std::make_unique<WalkFigures>(*this);
    }
    // Table "walks.STRATEGY", one row (WalkStatistics::table); none when nothing walked.
    [[nodiscard]] std::vector<file::StatTable> tables(const std::string& strategy) const override {
        if (!walks.attempted) return {};
        return {walks.table("walks." + strategy, strategy)};
    }
    [[nodiscard]] std::string text(const std::string& strategy) const override;

    std::optional<WalkOutcome> walk; // the walk of the proposal under way, if it made one
    WalkStatistics walks;
};

// The walks counted for strategy `i` of a run's statistics, whose mutation walks (its figures are WalkFigures).
[[nodiscard]] inline const WalkStatistics& walksOf(const MutationStatistics& stats, size_t i) {
    return static_cast<const WalkFigures&>(*stats.figures(i)).walks;
}

// Where a proposal records its walk: the proposing chain's figures (the mutation made them WalkFigures), or a
// record of this thread's that nobody reads when the proposal is made outside a chain (a test, a pre-run).
[[nodiscard]] std::optional<WalkOutcome>& walkRecord(Proposal& out);

// How a proposal whose manifold walk failed is counted: occluded, not reversible, or walk failed.
[[nodiscard]] RejectCause rejectCauseOf(WalkFailure f);

} // namespace lt
