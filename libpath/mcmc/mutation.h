// The contract every path-space mutation fulfils (after Mitsuba's libbidir: each mutator
// answers the same two questions, so the Metropolis-Hastings driver is one loop for all):
// * is it suitable for a path (its selection probability is then w_m s_m(x) / sum_j w_j s_j(x), taken
//   at both states, since suitability can differ between x and y), and
// * propose a path y from x, with Q(x -> y) = T(x -> y) / f*(y) and Q(y -> x) = T(y -> x) / f*(x),
//   both computed from the two paths as they are (markov_path.h), never from values cached on the way.
#pragma once

#include <string>

#include "math/rng.h"
#include "mcmc/markov_path.h"
#include "mcmc/mutation_figures.h"

namespace lt {

struct Proposal {
    MarkovPath y;
    double forwardQ = 0;               // T(x -> y) / f*(y), selection probability excluded
    double reverseQ = 0;               // T(y -> x) / f*(x)
    std::optional<RejectCause> failed; // no path proposed, and why
    // For the detailed-balance checks of the tests: the density the proposal actually sampled its new
    // vertices with (multiplied step by step while sampling) and the one recomputed from scratch for
    // the same sampling decisions.
    double sampledDensity = 0, recomputedDensity = 0;
    // The proposing chain's figures of this mutation (Mutation::makeFigures), which the mutation records into;
    // null when it has none or nobody counts them.
    MutationFigures* figures = nullptr;

    // A fresh proposal, its figures kept: what every propose() starts with.
    void reset() {
        MutationFigures* f = figures;
        *this = Proposal{};
        figures = f;
    }
};

// The end of every proposal: y re-evaluated from its vertices (false, with the cause in `failed`, when it
// carries nothing; the shadow rays of edges it shares with x are not traced again), then the two
// transition densities T(x -> y) and T(y -> x) (in the measure of what changed) turned into Q; `sampled`
// is what the proposal multiplied while sampling.
[[nodiscard]] inline bool evaluateProposal(const Scene& scene, const MarkovPath& x, Proposal& out) {
    out.failed = evaluatePath(scene, out.y, &x);
    return !out.failed;
}
inline void setTransitionDensities(Proposal& out, const MarkovPath& x, double sampled, double forwardT,
                                   double reverseT) {
    out.sampledDensity = sampled;
    out.recomputedDensity = forwardT;
    out.forwardQ = forwardT / out.y.target;
    out.reverseQ = reverseT / x.target;
}

class Mutation {
public:
    virtual ~Mutation() = default;
    [[nodiscard]] virtual std::string name() const = 0;
    [[nodiscard]] virtual bool suitable(const MarkovPath& x) const = 0;
    virtual void propose(const MarkovPath& x, Pcg32& rng, Proposal& out) const = 0;
    // A chain's object for the figures this mutation counts of its proposals beyond every strategy's counters
    // (mcmc/mutation_figures.h); none by default.
    [[nodiscard]] virtual std::unique_ptr<MutationFigures> makeFigures() const { return nullptr; }
};

} // namespace lt
