// Kelemen PSSMLT and multiplexed MLT over lt's BDPT (ALGORITHMS.md 8).
//
// Start-up (Veach-Guibas start-up bias removal, ALGORITHMS.md 1.3, in primary sample space as Kelemen and
// pbrt-v3 do): `startupSamples` independent primary samples estimate b = integral of f*; every chain
// then starts from one of them drawn in proportion to f*, and the image is scaled by that b. Multiplexed
// MLT estimates b per path length, gives each length a share of the chains in proportion to its b
// (systematic sampling over the chain index, so the share is exact in expectation), and starts each chain
// from that length's samples.
//
// Proposals: a large step (all coordinates fresh) with probability `largeStepProbability`, otherwise
// Kelemen's exponential small step on every coordinate (mcmc/primary_sample_vector.h). Both kernels are
// symmetric, so the acceptance is f*(u') / f*(u).
#pragma once

#include "mcmc/chain_run.h"
#include "mcmc/primary_sample_vector.h"

namespace lt {

enum class PrimarySpace { Kelemen, Multiplexed };

struct PrimarySpaceSettings {
    PrimarySpace space = PrimarySpace::Kelemen;
    BdptSettings bdpt;
    int unboundedEdges = 12;           // multiplexed: path-length bound when bdpt.maxDepth is -1
    double largeStepProbability = 0.3; // Mitsuba's default (ALGORITHMS.md 8)
    SmallStepKernel smallStep;
    uint64_t startupSamples = 100000; // Mitsuba's luminanceSamples; multiplexed: spread over the lengths
};

// Renders into `film` (its splats; the film's light-path count becomes the number of mutations).
// Throws lt::Error when the start-up finds no light at all.
ChainRunStats runPrimarySpaceChains(const Scene& scene, const PrimarySpaceSettings& space, const ChainRunSettings& run,
                                    SampleFilm& film, const ChainProgressCallback& progress,
                                    const std::atomic<bool>* stop, const ChainSnapshotCallback& snapshot = {});

} // namespace lt
