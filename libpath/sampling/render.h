// The render loop of every pixel estimator (sampling/pixel_estimator.h: BDPT, path tracing, ...):
// tiles x sample passes as work items, rendered in parallel and merged into the film strictly in item
// order (sampling/parallel_run.h), so that a given seed and sample count give a bit-identical film whatever
// the number of threads. It stops at the sample count, at the time limit (after
// the first pass, with the work items under way; at a pass's end for estimators whose samples credit
// neighbours and for runs that collect seeds), or when `stop` becomes true (Ctrl-C), and the film then holds every
// merged item: a valid, normalized, if noisier, result. Its clock, progress and snapshots are those of every run
// (sampling/run_clock.h).
#pragma once

#include "image/film.h"
#include "image/snapshot_schedule.h"
#include "sampling/bdpt.h"
#include "sampling/parallel_run.h"
#include "sampling/pixel_estimator.h"
#include "sampling/seed_reservoir.h"

namespace lt {

// Where a pixel sample's random numbers come from: independent uniform numbers (PCG32), or padded
// Owen-scrambled Sobol' points stratified over the pixel's samples (sampling/sobol_sampler.h).
enum class SamplerKind { Independent, Sobol };

struct RenderSettings {
    PathSettings paths;   // path length, Russian roulette and MIS of the estimator
    int spp = 16;         // samples per pixel (with timeLimit: an upper bound, 0 = none)
    double timeLimit = 0; // seconds; 0 = render exactly spp samples per pixel
    uint64_t seed = 0;
    SamplerKind sampler = SamplerKind::Independent; // estimators that work a tile at a time take Independent only
    int tileSize = 32;          // ignored by estimators with their own tiles (PixelEstimator::reuseTileSize)
    SnapshotSchedule snapshots; // checked at the end of every complete pass
};

struct RenderStats : RunRecord {
    uint64_t samples = 0;
    int passes = 0; // complete passes merged
};

// The random numbers of one pixel's sample in one pass (pixel: y * film width + x, full film): the render
// loop's, and those of estimators that work a tile at a time.
[[nodiscard]] IndependentSampler pixelSampler(uint64_t seed, int pass, uint64_t pixel);

// The resampling weight of a BDPT strategy path as a seed: strategyWeight (path/path_record.h), for
// camera strategies divided by the sum of the pixel filters at its raster position (film.h
// filterSum), so that the weights integrate f* over raster positions as the Markov chains' b does.
[[nodiscard]] double seedWeight(const SampleFilm& film, const StrategyPath& path);
// The same for another resampling weight of the path (a chain target's f* / p times the MIS weight).
[[nodiscard]] double seedWeight(const SampleFilm& film, const StrategyPath& path, double weight);
// A BDPT strategy path as a candidate seed path: its record, weighted by seedWeight.
[[nodiscard]] file::PathRecord seedCandidate(const Scene& scene, const SampleFilm& film, const StrategyPath& path,
                                             uint64_t stream, uint64_t offset);

// Renders `estimator` into `film`, which must have been made with the estimator's planes(). With `seeds`, every joined
// path the estimator forms becomes a candidate seed path (path/path_record.h) offered to the reservoir in work-item
// order, so the kept draws, too, do not depend on the thread count. Snapshots are taken at pass boundaries when
// settings.snapshots says so.
RenderStats render(const Scene& scene, const PixelEstimator& estimator, const RenderSettings& settings,
                   SampleFilm& film, const RunControl& control, SeedReservoir* seeds = nullptr);
} // namespace lt
