// The render loop of the pixel samplers (BDPT, path tracing): tiles x sample passes as work items,
// rendered in parallel and merged into the film strictly in item order (TBB parallel_pipeline with
// serial in-order stages), so that a given seed and sample count give a bit-identical film whatever the
// number of threads. It stops at the sample count, at the time limit, or when `stop` becomes true
// (Ctrl-C), and the film then holds every merged item: a valid, normalized, if noisier, result.
#pragma once

#include <atomic>
#include <functional>

#include "image/film.h"
#include "image/snapshot_schedule.h"
#include "sampling/bdpt.h"
#include "sampling/seed_reservoir.h"

namespace lt {

enum class PixelMethod { Bdpt, PathTracing };

struct RenderSettings {
    PixelMethod method = PixelMethod::Bdpt;
    BdptSettings bdpt;
    int spp = 16;         // samples per pixel (with timeLimit: an upper bound, 0 = none)
    double timeLimit = 0; // seconds; 0 = render exactly spp samples per pixel
    int threads = 0;      // 0 = all cores
    uint64_t seed = 0;
    int tileSize = 32;
    SnapshotSchedule snapshots; // checked at the end of every complete pass
};

struct RenderProgress {
    uint64_t samples = 0;      // camera samples merged so far
    uint64_t totalSamples = 0; // expected total (0 when only a time limit bounds the run)
    double wallSeconds = 0;    // rendering time: wall clock minus the time spent writing snapshots
    double cpuSeconds = 0;
    double snapshotSeconds = 0; // wall time spent in the snapshot callback so far
    int passesDone = 0;         // complete passes (one sample per pixel each)
};

struct RenderStats {
    uint64_t samples = 0;
    uint64_t rays = 0; // rays traced (closest hit and shadow)
    int passes = 0;    // complete passes merged
    double wallSeconds = 0, cpuSeconds = 0;
    SampleHealth health;
    bool interrupted = false;
    int snapshots = 0;
    double snapshotSeconds = 0;
};

using ProgressCallback = std::function<void(const RenderProgress&)>;
// Called at pass boundaries when settings.snapshots says so; its own duration is measured and kept out
// of the times it and later snapshots report.
using SnapshotCallback = std::function<void(const RenderProgress&, const SampleFilm&)>;

// The resampling weight of a BDPT strategy path as a seed: strategyWeight (path/path_record.h), for
// camera strategies divided by the sum of the pixel filters at its raster position (film.h
// filterSum), so that the weights integrate f* over raster positions as the Markov chains' b does.
[[nodiscard]] double seedWeight(const SampleFilm& film, const StrategyPath& path);
// A BDPT strategy path as a candidate seed path: its record, weighted by seedWeight.
[[nodiscard]] file::PathRecord seedCandidate(const Scene& scene, const SampleFilm& film, const StrategyPath& path,
                                             uint64_t stream, uint64_t offset);

// With `seeds`, every BDPT strategy path becomes a candidate seed path (path/path_record.h) offered to the
// reservoir in work-item order, so the kept draws, too, do not depend on the thread count.
RenderStats render(const Scene& scene, const RenderSettings& settings, SampleFilm& film,
                   const ProgressCallback& progress, const std::atomic<bool>* stop, SeedReservoir* seeds = nullptr,
                   const SnapshotCallback& snapshot = {});

} // namespace lt
