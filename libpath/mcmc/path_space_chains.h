// Path-space Metropolis light transport (Veach and Guibas 1997): chains whose
// states are whole paths, started from seed paths and mutated by a weighted mix of mutations.
//
// Start-up (Veach and Guibas 1997's start-up bias removal; MCMC survey, Sec. 2.5): the seed paths are independent
// draws in proportion to their weight (lt-seed --paths); a chain starts from one of them picked uniformly.
//
// Normalization (mcmc/normalization.h). The seed run's b is the mean of its n_s BDPT samples X_i, each
// X_i = P sum over the sample's strategies of seedWeight (P = pixels; an unbiased estimate of b). During
// the run every chain adds one more independent BDPT sample Y_j, at a uniformly chosen pixel, every
// 1 / `refineB` mutations, and the film is read with
//   b = (sum_i X_i + sum_j Y_j) / (n_s + n_r),
// unbiased for any n_r fixed independently of the values (a time limit decides n_r by the clock, not by
// the values), with variance Var(X) / (n_s + n_r): the scale error falls with the run instead of staying
// at the seed run's. The image estimator b / N sum f / f* is then consistent (the chains' start-up
// states still come from the seed run, whose bias vanishes as the chains mix) rather than unbiased over
// runs as with the seed b alone; that was the price of an error curve that keeps falling.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "formats/ltfile.h"
#include "formats/records.h"
#include "mcmc/chain_run.h"
#include "mcmc/markov_path.h"
#include "mcmc/mutation.h"
#include "mcmc/normalization.h"
#include "sampling/bdpt.h"

namespace lt {

struct WeightedMutation {
    const Mutation* mutation = nullptr;
    double weight = 1;
};

struct PathSpaceSeeds {
    std::vector<file::PathRecord> paths; // draws in proportion to weight
    NormalizationEstimate b;             // the seed run's estimate of the integral of f* over the image
};

// The share of b of one BDPT sample (sum of its strategies' seedWeight times the pixel count) through a
// uniformly chosen pixel of `film`, with random numbers keyed by (seed, index); `onPath`, when given,
// sees each strategy path (seedCandidate's input).
[[nodiscard]] double bdptSampleOfB(const Bdpt& bdpt, const SampleFilm& film, uint64_t seed, uint64_t index,
                                   const StrategyCallback* onPath = nullptr);

// The chains' start: the paths of a seed file (sampling/seed_file.h) and the seed run's b as the first
// samples of the estimate; throws lt::Error naming the file when b or its sample count is missing, or when its paths
// are not those of chains of paths from `minEdges` edges on (PathSettings::minDepth).
[[nodiscard]] PathSpaceSeeds seedsFromFile(file::Content&& content, int minEdges);

// Seed paths from a BDPT run of its own (what lt-seed --paths writes): at least `samples` camera
// samples (whole passes), `keep` draws. With a `target`, the draws are in proportion to it (b stays the
// integral of luminance: ChainRunSettings::luminanceNormalized).
[[nodiscard]] PathSpaceSeeds seedWithBdpt(const Scene& scene, const PathSettings& bdpt, uint64_t samples, size_t keep,
                                          uint64_t seed, const RunControl& control, const PathTarget& target = {});

// What the chains hand over after each round, in chain order:
// * every `every`-th state of each chain (counting its mutations): lt-mutate --dump-paths, for trace plots
//   and lt-inspect;
// * with `writeRound`, the chain-state stream (lt-mutate --stream): every state the image credited, with its
//   credit, so that an estimator downstream (lt-gradient --from-paths) sees the chains' samples exactly as
//   the image does. A proposal rejected with a > 0 is one record (credit a); a state the chain moved to is one
//   record when it leaves or the round ends (credit a when proposed, plus 1 - a of every proposal made from
//   it, as mcmc/metropolis.h ChainPosition credits it).
struct PathDump {
    uint64_t every = 0; // 0: none
    std::function<void(std::vector<file::PathRecord>&)> write;
    std::function<void(const file::ChainRound& figures, std::vector<file::EncodedChainStates>&& states)> writeRound;
};

// Renders into `film`. `refineB`: independent BDPT samples (with `bdpt`, the seed run's settings) per
// mutation added to b during the run (0: the seed run's b alone). The mutations must outlive the call. Throws lt::Error
// when no seed path fits the scene. `stats.strategies` gets one row per mutation.
// With a `target` the chains sample it instead of luminance (GDMLT, Lehtinen et al. 2013): every state's f* is
// re-evaluated after its mutation built it, and the mutation's Q = T / f* rescaled to match (mcmc/mutation.h);
// seeds.b stays the integral of luminance, and the film is read as ChainRunSettings::luminanceNormalized says.
ChainRunStats runPathSpaceChains(const Scene& scene, const PathSpaceSeeds& seeds,
                                 const std::vector<WeightedMutation>& mutations, const ChainRunSettings& run,
                                 const PathSettings& bdpt, double refineB, SampleFilm& film, const RunControl& control,
                                 const PathDump& dump = {}, const PathTarget& target = {});

} // namespace lt
