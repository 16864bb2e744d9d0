// What every Markov-chain run shares, whatever its state space: settings of the run (how long, how many
// chains, threads, seed, snapshots), its progress, and its outcome.
//
// Determinism: chains are independent, each with its own random streams keyed by (seed, chain index);
// they advance in rounds of a fixed number of mutations, in parallel, and their splats are merged into
// the film in chain order after each round. A given seed and mutation count therefore give the same
// film whatever the number of threads, and a time limit, a snapshot or Ctrl-C takes effect at the end of
// a round, when every chain's credit has been flushed: the film is then a complete estimate.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <vector>

#include "image/film.h"
#include "image/snapshot_schedule.h"
#include "mcmc/mutation_statistics.h"
#include "sampling/bdpt.h"

namespace lt {

struct ChainRunSettings {
    uint64_t mutations = 0; // total over all chains (0: only the time limit bounds the run)
    double timeLimit = 0;   // seconds, start-up included (0: none)
    int chains = 256;       // independent chains; more chains, better stratified, shorter each
    int threads = 0;        // 0 = all cores
    uint64_t seed = 0;
    int mutationsPerRound = 64;  // per chain between merges (granularity of snapshots)
    SnapshotSchedule snapshots;  // checked at the end of every round (sample counts: mutations per pixel)
};

struct ChainRunProgress {
    const char* phase = ""; // "start-up" or "chains"
    double fraction = -1;   // of the phase, when known
    uint64_t mutations = 0;
    uint64_t totalMutations = 0; // 0 when only a time limit bounds the run
    double wallSeconds = 0;      // since the start, snapshot writing excluded
    double cpuSeconds = 0;
    double snapshotSeconds = 0;
};

struct ChainRunStats {
    uint64_t mutations = 0;
    double wallSeconds = 0, cpuSeconds = 0, startupSeconds = 0;
    uint64_t rays = 0;
    double b = 0;                     // the normalization used: integral of f* over the image
    std::vector<double> bPerLength;   // multiplexed: b of each path length (index = edges)
    std::vector<int> chainsPerLength; // multiplexed: chains given to each path length
    uint64_t startupSamples = 0;
    MutationStatistics strategies;
    SampleHealth health;
    bool interrupted = false;
    int snapshots = 0;
    double snapshotSeconds = 0;
};

using ChainProgressCallback = std::function<void(const ChainRunProgress&)>;
using ChainSnapshotCallback = std::function<void(const ChainRunProgress&, const SampleFilm&)>;

} // namespace lt
