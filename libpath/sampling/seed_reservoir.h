// Candidate seed paths for the Markov chains, kept in bounded memory for any sample count.
//
// Chains start by resampling candidates in proportion to their weight (Veach-Guibas start-up bias
// removal; MCMC survey, Sec. 2.5). Keeping every candidate would need memory proportional to the sample
// count, so lt keeps K independent draws, each proportional to weight over ALL candidates seen: K
// weighted reservoirs of size one (Chao 1982) run at once. A reservoir replaces its path by the new
// candidate with probability w / W (W the weight seen so far), independently of the others. A chain then
// picks one of the K draws uniformly: that is a draw proportional to weight from the full candidate set,
// exactly what start-up needs.
#pragma once

#include <memory>
#include <vector>

#include "formats/records.h"
#include "math/rng.h"

namespace lt {

class SeedReservoir {
public:
    // `minEdges`: shorter paths are not candidates, and b leaves them out (the chains of the direct split, whose
    // target holds no path of the direct part: sampling/direct_split.h).
    SeedReservoir(size_t capacity, uint64_t seed, int minEdges = 1);

    // Offer one candidate (its weight is rec.weight; zero or non-finite weights, and paths shorter than minEdges,
    // are not candidates).
    void add(const file::PathRecord& rec);
    [[nodiscard]] int minEdges() const { return minEdges_; }

    [[nodiscard]] double totalWeight() const { return total_; }
    // b, the integral of f* over the image (MCMC survey, Eq. 12), from a run of `samples` camera samples
    // over `pixels` pixels: the candidates' weights sum to b times samples / pixels.
    [[nodiscard]] double normalization(uint64_t samples, double pixels) const {
        return samples > 0 ? total_ * pixels / double(samples) : 0.0;
    }
    [[nodiscard]] uint64_t candidates() const { return candidates_; }
    [[nodiscard]] size_t capacity() const { return slots_.size(); }
    // The K draws (fewer only when no candidate had weight); the same path may appear several times.
    [[nodiscard]] std::vector<file::PathRecord> draws() const;

private:
    std::vector<std::shared_ptr<const file::PathRecord>> slots_;
    Pcg32 rng_;
    int minEdges_;
    double total_ = 0;
    uint64_t candidates_ = 0;
};

} // namespace lt
