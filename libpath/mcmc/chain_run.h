// What every Markov-chain run shares, whatever its state space: settings of the run (how long, how many
// chains, threads, seed, snapshots), its progress, and its outcome.
//
// Determinism: chains are independent, each with its own random streams keyed by (seed, chain index);
// they advance in rounds of a fixed number of mutations, in parallel, and their splats are merged into
// the film in chain order after each round. A given seed and mutation count therefore give the same
// film whatever the number of threads, and a time limit, a snapshot or Ctrl-C takes effect at the end of
// a round, when every chain's credit has been flushed: the film is then a complete estimate.
//
// Normalization: chains splat with b = 1 and add independent samples of b to their own
// NormalizationEstimate as they run; after each round the runner takes them in chain order, and a
// snapshot or the end of the run scales the film by the estimate as it then stands (mcmc/normalization.h).
//
// Strata (multiplexed MLT's path lengths): the image is (b / N) sum_i f / f*(x_i), and its part of stratum k has
// mass (b / N) C_k in luminance, C_k the credit the chains gave to states of stratum k (the mutations spent there,
// in expectation). It is right only when C_k / N = b_k / b: a chain that samples f* spends that share of its time
// there in the limit, but finite runs do not. On a scene whose start-up never saw a length that holds most of b
// (a lamp seen directly, found later by a large step), no chain was there, C_k stayed near 0 while b_k entered
// b, and every other length came out b / (b - b_k) too bright (13 times on a public pool scene). So each stratum
// is read with its own b_k over its own credit:
//   I = sum_k (b_k / C_k) sum_{i in k} credit_i f / f*(x_i)    (all rounds)
//     = (1 / N) sum_i w_k(i) credit_i f / f*(x_i),   w_k = b_k / (C_k / N).
// The film cannot hold a plane per stratum (65 lengths at 1024^2), so it sums each round's splats of stratum k times
// w_k as it stands after that round (b_k, and the credits C_k and N so far, the round's own included), and is read
// with the factor 1 (not b). The weights carry b_k itself, not its share b_k / b: when a large step finds a
// length late (the lamp's b_k jumps from 0 to most of b), the rounds before keep the scale their own lengths had.
// Each stratum's mass follows its own b_k whatever the chains' visits: a stratum the chains never reach loses its own
// part alone, one they over- or under-visit keeps its scale. For chains that sample f*, C_k / N tends to b_k / b,
// and every round's b_k to the true one: the estimate is consistent, like the refined b, not unbiased at a fixed N;
// an early round's error of b_k stays in its splats, so the scale error falls somewhat slower than with one b read at
// the end. Determinism holds: the weights come from the chains' credits and samples merged in chain order.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "image/film.h"
#include "image/snapshot_schedule.h"
#include "mcmc/metropolis.h"
#include "mcmc/normalization.h"
#include "mcmc/mutation_statistics.h"
#include "sampling/bdpt.h"
#include "sampling/parallel_run.h"

namespace lt {

struct ChainRunSettings {
    uint64_t mutations = 0; // total over all chains (0: only the time limit bounds the run)
    double timeLimit = 0;   // seconds, start-up included (0: none)
    int chains = 256;       // independent chains; more chains, better stratified, shorter each
    uint64_t seed = 0;
    int mutationsPerRound = 64; // per chain between merges (granularity of snapshots)
    SnapshotSchedule snapshots; // checked at the end of every round (sample counts: mutations per pixel)
    // The chains sample a target f* other than luminance (GDMLT's): the normalization estimates the integral of
    // luminance (targetValue) instead, b_lum, which BDPT samples estimate well, and the film is read with
    // b = b_lum N / sum of credit x lum f / f*, the chains' own estimate of b_lum / b turned around (the image of
    // luminance sums to b_lum). Consistent like the refined b (path_space_chains.h); an integral of f* from BDPT
    // samples would not do: on caustic-mirror its relative standard error was 6 % where luminance's was 0.8 %,
    // and the image came out 22 % too dark.
    bool luminanceNormalized = false;
};

// The run's record (times, rays, snapshots, health, interruption) and what chains add to it.
struct ChainRunStats : RunRecord {
    uint64_t mutations = 0;
    double b = 0; // the normalization the film was read with at the end (ChainRunSettings::luminanceNormalized)
    double startupSeconds = 0;
    // The normalization b (integral of f* over the image; of luminance under
    // ChainRunSettings::luminanceNormalized) as it stood at the end, from the start-up's samples and those added
    // during the run (multiplexed: one stratum per path length, index = edges).
    NormalizationEstimate normalization;
    uint64_t startupSamples = 0; // samples of b the start-up drew (path space: of the seed run)
    double startupWork = 0;  // primary spaces: the start-up's work over its budget (it ends early once b is precise)
    double startupError = 0; // primary spaces: b's relative standard error when the start-up ended
    // multiplexed, per path length (index = edges): chains started there, and mutations spent there
    std::vector<uint64_t> chainsPerLength, mutationsPerLength;
    // With strata: each stratum's image weight w_k = b_k N / C_k after the last round (chain_run.h, top; 0 where no
    // credit went); the film is then read with b = 1.
    std::vector<double> stratumWeights;
    // Multiplexed MLT with an unbounded depth: the lengths the chains cover grew to `lengths` (from the start-up's
    // first bound) until the paths beyond carried under TailBound of b; the start-up's estimate of their b and its
    // standard error (mcmc/primary_space_chains.h). lengths 0: the depth was bounded.
    int lengths = 0;
    double tailB = 0, tailError = 0;
    uint64_t unusableSeeds = 0; // path space: seed draws that did not re-create in the scene
    MutationStatistics strategies;
};

// The run's figures at the end of a round (the chain-state stream's round header, file::ChainRound).
struct RoundEnd {
    uint64_t mutations = 0; // all chains' so far
    double b = 0;           // the normalization as it then stands
    uint64_t bSamples = 0;
    double wallSeconds = 0, cpuSeconds = 0;
};

// One Markov chain, whatever its state space.
class MarkovChain {
public:
    virtual ~MarkovChain() = default;
    // Run up to n mutations, crediting `image` (and flushing the current state's credit at the end);
    // `timeUp` is asked every 16 mutations. Returns the number of mutations done.
    virtual uint64_t advance(uint64_t n, ChainImage& image, const std::function<bool()>& timeUp) = 0;
    // Add the chain's counters to the run's.
    virtual void collect(MutationStatistics& strategies, SampleHealth& health) const = 0;

    uint64_t quota = 0; // mutations this chain is to run (all of them with only a time limit)
    uint64_t done = 0;
    // Independent samples of b drawn since the runner last took them (chain_run.h, top).
    NormalizationEstimate normalization;
};

// Throws lt::Error when `chains` chains cannot fit in the memory available (what one chain holds at the
// least: its state and proposal with their vertices, a round's splats): the one check of the chain count,
// for the tools before their start-up and for ChainRunner.
void requireChainMemory(int chains);

// The clock, progress and snapshots of a run, from its start (start-up included: RunControl::start) to its end.
class ChainRunner {
public:
    // Progress records count mutations as samples; a snapshot is the film read with the normalization as
    // it stands (RunProgress::b).
    ChainRunner(const ChainRunSettings& run, SampleFilm& film, const RunControl& control);

    // The run's threads, clock and stop flag, for its start-up too.
    [[nodiscard]] ParallelRun& parallel() { return parallel_; }
    // Seconds since the start, snapshot writing excluded.
    [[nodiscard]] double elapsed() const { return parallel_.elapsed(); }
    [[nodiscard]] bool stopped() const { return parallel_.stopped(); }
    void report(const char* phase, double fraction, uint64_t mutations) const;
    // Give every chain its quota: the run's mutations split evenly (or unbounded with a time limit).
    void assignQuotas(std::vector<std::unique_ptr<MarkovChain>>& chains) const;
    // Rounds until every quota is done, the time is up or Ctrl-C: chains advance in parallel, their splats
    // merge in chain order with b = 1 (ChainImage), and their samples of b join stats.normalization (which
    // holds the start-up's), by which snapshots and the end read the film. Fills the times, counts and
    // statistics of `stats` (which must carry the strategy names).
    // `afterRound`, when given, sees the chains after each round's merge, with the run's figures then.
    void run(std::vector<std::unique_ptr<MarkovChain>>& chains, ChainRunStats& stats,
             const std::function<void(std::vector<std::unique_ptr<MarkovChain>>&, const RoundEnd&)>& afterRound = {});
    // Close `stats` (its times and the b the film is read with); run() does it, and a run that ends without
    // chains (interrupted during start-up) calls it alone.
    void finish(ChainRunStats& stats) const;

private:
    const ChainRunSettings& run_;
    SampleFilm& film_;
    // The b the film is read with now: the normalization's, or under another target the luminance-normalized one.
    [[nodiscard]] double filmB(const ChainRunStats& stats) const;

    // Scales each stratum's splats of a round by w_k (top), after the round's credits and samples of b are in.
    void weighStrata(std::vector<ChainImage>& images, ChainRunStats& stats);

    ParallelRun parallel_;
    std::vector<double> stratumCredit_; // all rounds', per stratum
    uint64_t mutations_ = 0;
    double luminanceCredit_ = 0;
};

} // namespace lt
