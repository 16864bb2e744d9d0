// Path-space Metropolis light transport (Veach and Guibas 1997; ALGORITHMS.md 1.4, 2): chains whose
// states are whole paths, started from seed paths and mutated by a weighted mix of mutations.
//
// Start-up (ALGORITHMS.md 1.3): the seed paths are independent draws in proportion to their weight
// (lt-seed --paths); a chain starts from one of them picked uniformly, and the image is scaled by the
// seed run's b, so the average over runs is unbiased (Veach-Guibas start-up bias removal).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "formats/records.h"
#include "mcmc/chain_run.h"
#include "mcmc/mutation.h"
#include "sampling/bdpt.h"

namespace lt {

struct WeightedMutation {
    const Mutation* mutation = nullptr;
    double weight = 1;
};

struct PathSpaceSeeds {
    std::vector<file::PathRecord> paths; // draws in proportion to weight
    double b = 0;                        // integral of f* over the image (STAT normalization)
};

// Seed paths from a BDPT run of its own (what lt-seed --paths writes): at least `samples` camera
// samples (whole passes), `keep` draws.
[[nodiscard]] PathSpaceSeeds seedWithBdpt(const Scene& scene, const BdptSettings& bdpt, uint64_t samples, size_t keep,
                                          uint64_t seed, int threads, const std::atomic<bool>* stop);

// Every `every`-th state of each chain (counting its mutations), handed over in chain order after each
// round: lt-mutate --dump-paths, for trace plots and lt-inspect.
struct PathDump {
    uint64_t every = 0; // 0: none
    std::function<void(std::vector<file::PathRecord>&)> write;
};

// Renders into `film`. The mutations must outlive the call. Throws lt::Error when no seed path fits the
// scene. `stats.strategies` gets one row per mutation.
ChainRunStats runPathSpaceChains(const Scene& scene, const PathSpaceSeeds& seeds,
                                 const std::vector<WeightedMutation>& mutations, const ChainRunSettings& run,
                                 SampleFilm& film, const ChainProgressCallback& progress, const std::atomic<bool>* stop,
                                 const ChainSnapshotCallback& snapshot = {}, const PathDump& dump = {});

} // namespace lt
