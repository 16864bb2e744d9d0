#include "sampling/render.h"

#include <oneapi/tbb/parallel_pipeline.h>
#include <oneapi/tbb/task_arena.h>

#include <chrono>
#include <ctime>
#include <memory>

#include "math/error.h"
#include "path/path_record.h"
#include "sampling/path_tracer.h"

namespace lt {

namespace {

struct WorkItem {
    uint64_t index = 0;
    int pass = 0;
    PixelRect rect;
    TileResult result;
    SampleHealth health;
    std::vector<file::PathRecord> candidates;
};

double cpuSeconds() { return double(std::clock()) / CLOCKS_PER_SEC; }

} // namespace

double seedWeight(const SampleFilm& film, const StrategyPath& path) {
    const double w = strategyWeight(path);
    if (path.t == 1) return w;
    const double h = film.filterSum(path.raster);
    return h > 0 ? w / h : 0.0;
}

file::PathRecord seedCandidate(const Scene& scene, const SampleFilm& film, const StrategyPath& path, uint64_t stream,
                               uint64_t offset) {
    file::PathRecord rec = toPathRecord(scene, path, stream, offset);
    rec.weight = seedWeight(film, path);
    return rec;
}

RenderStats render(const Scene& scene, const RenderSettings& settings, SampleFilm& film,
                   const ProgressCallback& progress, const std::atomic<bool>* stop, SeedReservoir* seeds,
                   const SnapshotCallback& snapshot) {
    if (settings.spp < 0 || (settings.spp == 0 && !(settings.timeLimit > 0)))
        throw Error("give a positive sample count or a time limit");
    const Bdpt bdpt(scene, settings.bdpt);
    const PathTracer pt(scene, settings.bdpt);
    const PixelRect window = film.window();
    const int ts = std::max(1, settings.tileSize);
    const int tilesX = (window.width() + ts - 1) / ts, tilesY = (window.height() + ts - 1) / ts;
    const uint64_t tilesPerPass = uint64_t(tilesX) * uint64_t(tilesY);
    const uint64_t maxPasses = settings.spp > 0 ? uint64_t(settings.spp) : UINT64_MAX;

    const auto start = std::chrono::steady_clock::now();
    const double cpuStart = cpuSeconds();
    auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };

    RenderStats stats;
    SnapshotSchedule schedule = settings.snapshots;
    const uint64_t raysBefore = EmbreeAccel::rayCount();
    uint64_t nextItem = 0;
    bool timeUp = false;
    const int threads = settings.threads > 0 ? settings.threads : tbb::this_task_arena::max_concurrency();
    tbb::task_arena arena(threads);
    arena.execute([&] {
        tbb::parallel_pipeline(
            size_t(2 * threads + 2),
            // 1. Issue work items in a fixed order: pass by pass, tile by tile.
            tbb::make_filter<void, WorkItem*>(tbb::filter_mode::serial_in_order,
                                              [&](tbb::flow_control& fc) -> WorkItem* {
                                                  const uint64_t pass = nextItem / tilesPerPass;
                                                  if ((stop && stop->load()) || pass >= maxPasses) {
                                                      fc.stop();
                                                      return nullptr;
                                                  }
                                                  // A time limit ends the run at a pass boundary.
                                                  if (nextItem % tilesPerPass == 0 && settings.timeLimit > 0 &&
                                                      elapsed() >= settings.timeLimit && pass > 0) {
                                                      timeUp = true;
                                                      fc.stop();
                                                      return nullptr;
                                                  }
                                                  auto* item = new WorkItem;
                                                  item->index = nextItem;
                                                  item->pass = int(pass);
                                                  const uint64_t tile = nextItem % tilesPerPass;
                                                  const int tx = int(tile % uint64_t(tilesX)),
                                                            ty = int(tile / uint64_t(tilesX));
                                                  item->rect = {window.x0 + tx * ts, window.y0 + ty * ts,
                                                                std::min(window.x1, window.x0 + (tx + 1) * ts),
                                                                std::min(window.y1, window.y0 + (ty + 1) * ts)};
                                                  ++nextItem;
                                                  return item;
                                              }) &
                // 2. Render an item: one sample per pixel of its tile, each pixel sample with its own
                //    random stream keyed by (seed, pass, pixel).
                tbb::make_filter<WorkItem*, WorkItem*>(
                    tbb::filter_mode::parallel,
                    [&](WorkItem* item) -> WorkItem* {
                        TileResult& r = item->result;
                        r.rect = item->rect;
                        r.sum.assign(r.rect.area() * 3, 0.0);
                        r.count.assign(r.rect.area(), 0);
                        std::vector<Splat> splats;
                        uint64_t pixel = 0;
                        const StrategyCallback collect = [&](const StrategyPath& sp) {
                            item->candidates.push_back(seedCandidate(scene, film, sp, pixel, uint64_t(item->pass)));
                        };
                        for (int y = r.rect.y0; y < r.rect.y1; ++y)
                            for (int x = r.rect.x0; x < r.rect.x1; ++x) {
                                pixel = uint64_t(y) * uint64_t(scene.camera.film().width) + uint64_t(x);
                                // Initial state and stream both depend on the pixel: PCG streams that
                                // differ only in their increment are correlated (Vigna 2018).
                                IndependentSampler sampler(
                                    mixBits(mixBits(settings.seed ^ mixBits(uint64_t(item->pass))) + pixel), pixel);
                                const Vec2 raster = film.sampleRaster(x, y, sampler.next2D());
                                Spectrum L;
                                if (settings.method == PixelMethod::Bdpt) {
                                    splats.clear();
                                    L = bdpt.sample(raster, sampler, splats, item->health, seeds ? &collect : nullptr);
                                    for (const auto& s : splats)
                                        r.splats.push_back({s.raster, s.value});
                                    ++r.lightPaths;
                                } else {
                                    L = pt.sample(raster, sampler, item->health);
                                }
                                const size_t i = size_t(y - r.rect.y0) * size_t(r.rect.width()) + size_t(x - r.rect.x0);
                                for (int c = 0; c < 3; ++c)
                                    r.sum[3 * i + size_t(c)] += L[c];
                                ++r.count[i];
                            }
                        EmbreeAccel::flushRayCount();
                        return item;
                    }) &
                // 3. Merge in issue order.
                tbb::make_filter<WorkItem*, void>(tbb::filter_mode::serial_in_order, [&](WorkItem* item) {
                    std::unique_ptr<WorkItem> owned(item);
                    film.merge(item->result);
                    if (seeds)
                        for (const auto& c : item->candidates)
                            seeds->add(c);
                    stats.samples += item->result.rect.area();
                    stats.health.nonFinite += item->health.nonFinite;
                    const bool passEnd = (item->index + 1) % tilesPerPass == 0;
                    if (passEnd) ++stats.passes;
                    RenderProgress p;
                    p.samples = stats.samples;
                    p.totalSamples = settings.timeLimit > 0 ? 0 : maxPasses * window.area();
                    p.wallSeconds = elapsed() - stats.snapshotSeconds;
                    p.cpuSeconds = cpuSeconds() - cpuStart;
                    p.snapshotSeconds = stats.snapshotSeconds;
                    p.passesDone = stats.passes;
                    if (passEnd && snapshot && schedule.due(p.wallSeconds, double(stats.passes))) {
                        const double t0 = elapsed();
                        snapshot(p, film);
                        ++stats.snapshots;
                        stats.snapshotSeconds += elapsed() - t0;
                    }
                    if (progress) progress(p);
                }));
    });
    stats.wallSeconds = elapsed() - stats.snapshotSeconds;
    stats.cpuSeconds = cpuSeconds() - cpuStart;
    stats.rays = EmbreeAccel::rayCount() - raysBefore;
    stats.interrupted = stop && stop->load() && !timeUp && uint64_t(stats.passes) < maxPasses;
    return stats;
}

} // namespace lt
