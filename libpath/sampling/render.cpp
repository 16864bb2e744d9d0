#include "sampling/render.h"

#include <oneapi/tbb/parallel_pipeline.h>
#include <oneapi/tbb/task_arena.h>

#include <memory>

#include "math/error.h"
#include "path/path_record.h"
#include "sampling/path_tracer.h"
#include "sampling/sobol_sampler.h"

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

} // namespace

std::unique_ptr<PixelEstimator> makePixelEstimator(PixelMethod method, const Scene& scene,
                                                   const PathSettings& settings) {
    if (method == PixelMethod::PathTracing) return std::make_unique<PathTracer>(scene, settings);
    return std::make_unique<Bdpt>(scene, settings);
}

IndependentSampler pixelSampler(uint64_t seed, int pass, uint64_t pixel) {
    // Initial state and stream both depend on the pixel: PCG streams that differ only in their increment
    // are correlated (Vigna 2018).
    return IndependentSampler(mixBits(mixBits(seed ^ mixBits(uint64_t(pass))) + pixel), pixel);
}

double seedWeight(const SampleFilm& film, const StrategyPath& path) {
    return seedWeight(film, path, strategyWeight(path));
}

double seedWeight(const SampleFilm& film, const StrategyPath& path, double w) {
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

RenderStats render(const Scene& scene, const PixelEstimator& estimator, const RenderSettings& settings,
                   SampleFilm& film, const RunProgressCallback& progress, const std::atomic<bool>* stop,
                   SeedReservoir* seeds, const RunSnapshotCallback& snapshot) {
    if (settings.spp < 0 || (settings.spp == 0 && !(settings.timeLimit > 0)))
        throw Error("give a positive sample count or a time limit");
    if (film.planes() != estimator.planes())
        throw Error("the film's planes are not the estimator's (make the film with estimator.planes())");
    const PixelRect window = film.window();
    const int reuse = estimator.reuseTileSize();
    if (reuse > 0 && settings.sampler != SamplerKind::Independent)
        throw Error("an estimator that works a tile at a time draws its own independent numbers: no other sampler");
    const int ts = reuse > 0 ? reuse : std::max(1, settings.tileSize);
    // A jittered grid needs one more tile per row and column to cover the window.
    const int extra = reuse > 0 ? 1 : 0;
    const int tilesX = (window.width() + ts - 1) / ts + extra, tilesY = (window.height() + ts - 1) / ts + extra;
    const uint64_t tilesPerPass = uint64_t(tilesX) * uint64_t(tilesY);
    const uint64_t maxPasses = settings.spp > 0 ? uint64_t(settings.spp) : UINT64_MAX;
    // A run ends at a pass's end when a pixel's value needs the whole pass (samples credit neighbours), and
    // when it collects seeds: their normalization b = total x pixels / samples (sampling/seed_reservoir.h)
    // estimates the image's integral only if every pixel has as many samples.
    const bool wholePasses = estimator.creditsNeighbours() || seeds != nullptr;

    RunClock clock;
    RenderStats stats;
    SnapshotSchedule schedule = settings.snapshots;
    const uint64_t totalSamples = settings.timeLimit > 0 ? 0 : maxPasses * window.area();
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
                                                  // A time limit ends the run after the first pass: at
                                                  // the next work item, or at the next pass boundary when
                                                  // whole passes are needed (above).
                                                  if (settings.timeLimit > 0 && pass > 0 &&
                                                      (!wholePasses || nextItem % tilesPerPass == 0) &&
                                                      clock.wallSeconds() >= settings.timeLimit) {
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
                                                  int ox = window.x0, oy = window.y0;
                                                  if (reuse > 0) { // the same grid offset for the whole pass
                                                      const uint64_t j = mixBits(settings.seed ^ mixBits(pass + 1));
                                                      ox -= int(j % uint64_t(ts));
                                                      oy -= int((j >> 32) % uint64_t(ts));
                                                  }
                                                  item->rect = {std::max(window.x0, ox + tx * ts),
                                                                std::max(window.y0, oy + ty * ts),
                                                                std::min(window.x1, ox + (tx + 1) * ts),
                                                                std::min(window.y1, oy + (ty + 1) * ts)};
                                                  item->rect.x1 = std::max(item->rect.x0, item->rect.x1);
                                                  item->rect.y1 = std::max(item->rect.y0, item->rect.y1);
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
                        if (reuse > 0) {
                            if (r.rect.area() > 0)
                                estimator.estimateTile({r.rect, settings.seed, item->pass, r, item->health});
                            EmbreeAccel::flushRayCount();
                            return item;
                        }
                        std::vector<Splat> splats;
                        std::vector<PlaneValue> planeValues;
                        uint64_t pixel = 0;
                        const StrategyCallback collect = [&](const StrategyPath& sp) {
                            item->candidates.push_back(seedCandidate(scene, film, sp, pixel, uint64_t(item->pass)));
                        };
                        // One pixel sample; generic over the sampler so that its calls need no dispatch here.
                        const auto estimatePixel = [&](int x, int y, auto& sampler) {
                            const Vec2 raster = film.sampleRaster(x, y, sampler.next2D());
                            splats.clear();
                            planeValues.clear();
                            PixelSample out{x, y, splats, planeValues, item->health, seeds ? &collect : nullptr};
                            const Spectrum L = estimator.estimate(raster, sampler, out);
                            r.splats.insert(r.splats.end(), splats.begin(), splats.end());
                            for (const auto& v : planeValues)
                                r.planeValues.push_back({v.plane, x + v.dx, y + v.dy, v.value});
                            if (estimator.tracesLightPaths()) ++r.lightPaths;
                            const size_t i = size_t(y - r.rect.y0) * size_t(r.rect.width()) + size_t(x - r.rect.x0);
                            for (int c = 0; c < 3; ++c)
                                r.sum[3 * i + size_t(c)] += L[c];
                            ++r.count[i];
                        };
                        for (int y = r.rect.y0; y < r.rect.y1; ++y)
                            for (int x = r.rect.x0; x < r.rect.x1; ++x) {
                                pixel = uint64_t(y) * uint64_t(scene.camera.film().width) + uint64_t(x);
                                if (settings.sampler == SamplerKind::Sobol) {
                                    SobolSampler sampler(settings.seed, pixel, uint32_t(item->pass));
                                    estimatePixel(x, y, sampler);
                                } else {
                                    IndependentSampler sampler = pixelSampler(settings.seed, item->pass, pixel);
                                    estimatePixel(x, y, sampler);
                                }
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
                    if (passEnd) {
                        film.endPass();
                        ++stats.passes;
                    }
                    double fraction = -1;
                    if (totalSamples > 0)
                        fraction = double(stats.samples) / double(totalSamples);
                    else if (settings.timeLimit > 0)
                        fraction = std::min(1.0, clock.wallSeconds() / settings.timeLimit);
                    RunProgress p = clock.progress("render", fraction, stats.samples, totalSamples);
                    p.passesDone = stats.passes;
                    if (passEnd && snapshot && schedule.due(p.wallSeconds, double(stats.passes)))
                        clock.snapshot(
                            snapshot, p, [&] { return film.toBuffer(); }, stats);
                    if (progress) progress(p);
                }));
    });
    clock.close(stats);
    stats.interrupted = stop && stop->load() && !timeUp && uint64_t(stats.passes) < maxPasses;
    return stats;
}

} // namespace lt
