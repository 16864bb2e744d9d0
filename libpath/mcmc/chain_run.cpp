#include "mcmc/chain_run.h"

#include "util/memory_budget.h"

namespace lt {

void requireChainMemory(int chains) {
    constexpr double MinBytesPerChain = 16 << 10;
    requireMemory(double(chains) * MinBytesPerChain, "a run of " + std::to_string(chains) + " chains");
}

ChainRunner::ChainRunner(const ChainRunSettings& run, SampleFilm& film, const RunControl& control)
    : run_(run), film_(film), parallel_(control) {
    requireChainMemory(run.chains);
}

void ChainRunner::report(const char* phase, double fraction, uint64_t mutations) const {
    parallel_.report(parallel_.clock().progress(phase, fraction, mutations, run_.mutations));
}

void ChainRunner::assignQuotas(std::vector<std::unique_ptr<MarkovChain>>& chains) const {
    const uint64_t n = chains.size();
    for (uint64_t c = 0; c < n; ++c)
        chains[c]->quota = run_.mutations > 0 ? run_.mutations / n + (c < run_.mutations % n) : ~uint64_t(0);
}

void ChainRunner::run(
    std::vector<std::unique_ptr<MarkovChain>>& chains, ChainRunStats& stats,
    const std::function<void(std::vector<std::unique_ptr<MarkovChain>>&, const RoundEnd&)>& afterRound) {
    const double pixels = double(film_.width()) * double(film_.height());
    SnapshotSchedule schedule = run_.snapshots;
    // A time limit never ends a run before its first round: a start-up that outlasts --time still gives
    // an image (the start-up time is in the statistics).
    const auto overTime = [&] { return mutations_ > 0 && run_.timeLimit > 0 && elapsed() >= run_.timeLimit; };
    const auto timeUp = [&] { return overTime() || stopped(); };
    for (;;) {
        bool remaining = false;
        for (const auto& c : chains)
            remaining |= c->done < c->quota;
        if (!remaining || overTime()) break;
        if (stopped()) {
            stats.interrupted = true;
            break;
        }
        // The chains advance in parallel and their splats merge in chain order (in parallel over the film's rows):
        // the film does not depend on which thread ran which chain.
        const size_t strata = stats.normalization.strata();
        std::vector<ChainImage> images(chains.size(), ChainImage(1 / pixels, strata));
        std::vector<uint64_t> done(chains.size(), 0);
        std::vector<const std::vector<Splat>*> splats;
        uint64_t roundMutations = 0;
        parallel_.forEach(
            chains.size(),
            [&](uint64_t c) {
                MarkovChain& chain = *chains[c];
                const uint64_t n = std::min<uint64_t>(uint64_t(run_.mutationsPerRound), chain.quota - chain.done);
                done[c] = chain.advance(n, images[c], timeUp);
                chain.done += done[c];
            },
            [&](uint64_t c) {
                splats.push_back(&images[c].splats());
                luminanceCredit_ += images[c].luminanceCredit();
                roundMutations += done[c];
                stats.normalization.take(chains[c]->normalization);
            });
        if (strata > 1) weighStrata(images, stats);
        parallel_.execute([&] { film_.mergeSplats(splats, roundMutations); });
        mutations_ += roundMutations;
        const double wall = elapsed();
        if (afterRound)
            afterRound(chains,
                       {mutations_, filmB(stats), stats.normalization.samples(), wall, parallel_.clock().cpuSeconds()});
        double fraction = run_.mutations > 0 ? double(mutations_) / double(run_.mutations) : -1;
        if (run_.timeLimit > 0) fraction = std::max(fraction, std::min(1.0, wall / run_.timeLimit));
        if (parallel_.snapshots() && schedule.due(wall, double(mutations_) / pixels)) {
            RunProgress p = parallel_.clock().progress("chains", fraction, mutations_, run_.mutations);
            p.b = filmB(stats);
            parallel_.snapshot(
                p, [&] { return film_.toBuffer(p.b); }, stats);
        }
        report("chains", fraction, mutations_);
    }
    if (stopped()) stats.interrupted = true;
    for (const auto& c : chains)
        c->collect(stats.strategies, stats.health);
    stats.mutations = mutations_;
    finish(stats);
}

void ChainRunner::weighStrata(std::vector<ChainImage>& images, ChainRunStats& stats) {
    // w_k = b_k / (C_k / C) (chain_run.h, top), with this round's credit in C_k and C.
    const NormalizationEstimate& b = stats.normalization;
    stratumCredit_.resize(b.strata(), 0.0);
    for (const ChainImage& image : images)
        for (size_t k = 0; k < b.strata(); ++k)
            stratumCredit_[k] += image.stratumCredit()[k];
    double credit = 0;
    for (const double c : stratumCredit_)
        credit += c;
    stats.stratumWeights.assign(b.strata(), 0.0);
    for (size_t k = 0; k < b.strata(); ++k)
        if (stratumCredit_[k] > 0) stats.stratumWeights[k] = b.stratumB(k) / (stratumCredit_[k] / credit);
    for (ChainImage& image : images)
        for (size_t i = 0; i < image.splats().size(); ++i)
            image.splats()[i].value *= stats.stratumWeights[image.strata()[i]];
}

double ChainRunner::filmB(const ChainRunStats& stats) const {
    if (stats.normalization.strata() > 1) return 1; // the strata's splats carry their b_k (top)
    const double b = stats.normalization.b();
    if (!run_.luminanceNormalized) return b;
    return luminanceCredit_ > 0 ? b * double(mutations_) / luminanceCredit_ : 0.0;
}

void ChainRunner::finish(ChainRunStats& stats) const {
    stats.b = filmB(stats);
    parallel_.clock().close(stats);
}

} // namespace lt
