// Per-strategy counters of a Markov-chain run (after Tungsten's acceptance statistics): what was
// proposed, what was accepted, and why the rest was rejected. lt-mutate prints them as a table and
// stores them in the output's STAT chunk.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "formats/records.h"
#include "mcmc/mutation_figures.h"

namespace lt {

// Why a proposal had no chance: a proposal that was evaluated and lost the Metropolis-Hastings draw is
// "rejected by chance" (the complement of the acceptance probability), not one of these.
enum class RejectCause : int {
    ZeroContribution = 0, // the proposed path carries no light (absorbed, missed the light, BSDF zero)
    Occluded,             // a connection or a deterministic segment was blocked
    LeftImage,            // the proposal's camera ray lands outside the sensor
    ConfigurationChanged, // a perturbation met a different kind of vertex than the path had
    NonFinite,            // NaN or Inf: dropped and counted (no NaN reaches an output)
    WalkFailed,           // a manifold walk did not reach its target (diverged, TIR, left the surface, singular)
    NotReversible,        // the move back from the proposal could not return to the state: the manifold walk back
                          // did not (ME Sec. 5.1), or the proposal crosses a portal where the portal perturbation
                          // would pick another edge or pivot
    Missed,               // a ray from a fixed point (the portal perturbation's pivot) hit nothing, or no light
                          // where the path needs its light vertex
    Count
};
[[nodiscard]] const char* rejectCauseName(RejectCause c);

struct StrategyCounters {
    uint64_t proposed = 0;
    uint64_t accepted = 0;
    double acceptance = 0; // sum of the acceptance probabilities
    std::array<uint64_t, size_t(RejectCause::Count)> rejected{};
    double seconds = 0; // CPU time spent proposing and evaluating

    void merge(const StrategyCounters& o);
};

class MutationStatistics {
public:
    // `figures`, when given, one per strategy (null for a strategy without figures of its own).
    explicit MutationStatistics(std::vector<std::string> strategies = {},
                                std::vector<std::unique_ptr<MutationFigures>> figures = {});
    MutationStatistics(const MutationStatistics& o);
    MutationStatistics& operator=(const MutationStatistics& o);
    MutationStatistics(MutationStatistics&&) = default;
    MutationStatistics& operator=(MutationStatistics&&) = default;

    [[nodiscard]] const std::vector<std::string>& strategies() const { return names_; }
    StrategyCounters& operator[](size_t i) { return counters_[i]; }
    [[nodiscard]] const StrategyCounters& operator[](size_t i) const { return counters_[i]; }
    // Strategy i's own figures (mcmc/mutation_figures.h), or null.
    [[nodiscard]] MutationFigures* figures(size_t i) { return figures_[i].get(); }
    [[nodiscard]] const MutationFigures* figures(size_t i) const { return figures_[i].get(); }
    void merge(const MutationStatistics& o);

    // The table as stored in files: one row per strategy; columns proposed, accepted, acceptance (mean
    // probability), one column per rejection cause, seconds.
    [[nodiscard]] file::StatTable table(const std::string& name = "strategies") const;
    // The tables of the strategies' own figures (the walks of those that walked: "walks.NAME").
    [[nodiscard]] std::vector<file::StatTable> figureTables() const;
    // The same as aligned text for a terminal, with each strategy's own figures.
    [[nodiscard]] std::string text() const;

private:
    std::vector<std::string> names_;
    std::vector<StrategyCounters> counters_;
    std::vector<std::unique_ptr<MutationFigures>> figures_; // one per strategy
};

} // namespace lt
