// What a mutation counts of its own proposals beyond what every strategy's counters hold (mcmc/
// mutation_statistics.h): the manifold walks of the manifold perturbation and of HSLT's mutation, say (ME Sec. 4's and
// HSLT Table 3's figures). A mutation that has such figures makes one object per chain (Mutation::makeFigures);
// the chain hands it to the mutation with each proposal (Proposal::figures), settles it with the proposal's
// acceptance, and the run merges the chains' objects in chain order, so the figures, too, do not depend on the
// thread count.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "formats/records.h"

namespace lt {

class MutationFigures {
public:
    virtual ~MutationFigures() = default;
    // The proposal last made ends with acceptance probability `a` (0 when it failed).
    virtual void settle(double a) = 0;
    // Adds another chain's figures (of the same mutation).
    virtual void merge(const MutationFigures& other) = 0;
    [[nodiscard]] virtual std::unique_ptr<MutationFigures> clone() const = 0;
    // The figures as files store them, and as text for a terminal (empty: nothing to report), for the strategy
    // named `strategy`.
    [[nodiscard]] virtual std::vector<file::StatTable> tables(const std::string& strategy) const = 0;
    [[nodiscard]] virtual std::string text(const std::string& strategy) const = 0;
};

} // namespace lt
