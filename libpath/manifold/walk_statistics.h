// Counters of manifold walks, the figures ME section 4 and HSLT Table 3 report (92-98 % converged in 2-3
// iterations; HSLT: generation rate, non-reversible walks, iterations per successful walk and per walk):
// attempted, converged, iterations (mean, max), failures by cause, chain lengths, the mean acceptance of
// the proposals by chain length, and the projection order of HSLT's walks.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <ostream>
#include <string>

#include "formats/records.h"
#include "manifold/manifold_walk.h"

namespace lt {

// HSLT Sec. 5.2's jump after a failed walk: not tried, tried (the walk failed on a path that can jump) or
// proposed (valid both ways: its acceptance counted apart).
enum class JumpOutcome : uint8_t { None, Tried, Proposed };

// One walk as the statistics count it: how it ended, its iterations, the vertices of its chain.
struct WalkOutcome {
    WalkFailure failure = WalkFailure::None;
    int iterations = 0;
    size_t chainLength = 0;
    std::optional<bool> fromEye; // HSLT's walks: projected from the eye (else from the light)
    JumpOutcome jump = JumpOutcome::None;
};

struct WalkStatistics {
    uint64_t attempted = 0;
    uint64_t converged = 0;
    uint64_t iterationsConverged = 0;                 // summed over converged walks
    uint64_t iterationsAll = 0;                       // summed over all walks
    uint64_t fromEye = 0, fromLight = 0;              // HSLT's projection orders
    int maxIterations = 0;                            // over converged walks
    std::array<uint64_t, WalkFailureCount> byCause{}; // indexed by WalkFailure (None = converged)
    std::map<size_t, uint64_t> chainLengths;          // vertices per walked chain (endpoints included)
    std::map<size_t, double> acceptanceByLength;      // acceptance probabilities summed, by chain length
    uint64_t jumpsTried = 0, jumpsProposed = 0;       // HSLT's jumps between subspaces
    double jumpAcceptance = 0;                        // summed over proposed jumps

    void add(const WalkOutcome& w);
    void add(const WalkResult& r, size_t chainLength) {
        add({r.failure, r.iterations, chainLength, std::nullopt, JumpOutcome::None});
    }
    // The acceptance probability of the proposal that made this walk (0 if nothing was proposed), by chain
    // length (a jump proposed after a failed walk included) and, for a jump, also apart.
    void addAcceptance(const WalkOutcome& w, double a);
    void merge(const WalkStatistics& o);
    [[nodiscard]] double convergedFraction() const { return attempted ? double(converged) / double(attempted) : 0; }
    [[nodiscard]] double meanIterations() const {
        return converged ? double(iterationsConverged) / double(converged) : 0;
    }
    [[nodiscard]] double meanIterationsAll() const { return attempted ? double(iterationsAll) / double(attempted) : 0; }
    // A readable table: one line per figure, failures with their share of all walks.
    void print(std::ostream& out) const;
    // The figures as a file's statistics table (one row, `row`): attempted, converged, mean and max
    // iterations, one column per failure cause.
    [[nodiscard]] file::StatTable table(const std::string& name, const std::string& row) const;
};

} // namespace lt
