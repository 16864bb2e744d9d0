#include "sampling/render.h"

#include <algorithm>

#include "util/error.h"
#include "path/path_record.h"
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

// The work items of a pass: the film window cut into tiles, row after row. An estimator that works a tile at a
// time has its own tile size, and the grid moves by a random offset every pass ([GDPR] Sec. 3.2, tile jitter):
// a jittered grid needs one more tile per row and column to cover the window.
class TileGrid {
public:
    TileGrid(const PixelRect& window, int reuse, int tileSize, uint64_t seed)
        : window_(window), reuse_(reuse), size_(reuse > 0 ? reuse : std::max(1, tileSize)), seed_(seed) {
        const int extra = reuse > 0 ? 1 : 0;
        tilesX_ = (window.width() + size_ - 1) / size_ + extra;
        tilesY_ = (window.height() + size_ - 1) / size_ + extra;
    }

    [[nodiscard]] uint64_t tilesPerPass() const { return uint64_t(tilesX_) * uint64_t(tilesY_); }

    // The pixels of tile `tile` of pass `pass`, clipped to the window (empty where a jittered tile lies outside).
    [[nodiscard]] PixelRect rect(uint64_t tile, uint64_t pass) const {
        const int tx = int(tile % uint64_t(tilesX_)), ty = int(tile / uint64_t(tilesX_));
        int ox = window_.x0, oy = window_.y0;
        if (reuse_ > 0) { // the same grid offset for the whole pass
            const uint64_t j = mixBits(seed_ ^ mixBits(pass + 1));
            ox -= int(j % uint64_t(size_));
            oy -= int((j >> 32) % uint64_t(size_));
        }
        PixelRect r{std::max(window_.x0, ox + tx * size_), std::max(window_.y0, oy + ty * size_),
                    std::min(window_.x1, ox + (tx + 1) * size_), std::min(window_.y1, oy + (ty + 1) * size_)};
        r.x1 = std::max(r.x0, r.x1);
        r.y1 = std::max(r.y0, r.y1);
        return r;
    }

private:
    PixelRect window_;
    int reuse_, size_;
    uint64_t seed_;
    int tilesX_ = 0, tilesY_ = 0;
};

// One work item: one sample per pixel of its tile, each pixel sample with its own random stream keyed by (seed,
// pass, pixel), or the estimator's own work on the tile when it works a tile at a time. With `collect`, every
// joined path becomes a candidate seed path of the item.
void renderItem(const Scene& scene, const PixelEstimator& estimator, const RenderSettings& settings,
                const SampleFilm& film, bool collect, WorkItem& item) {
    TileResult& r = item.result; // a slot reused by later items: every field set anew
    r.rect = item.rect;
    r.sum.assign(r.rect.area() * 3, 0.0);
    r.count.assign(r.rect.area(), 0);
    r.splats.clear();
    r.planeValues.clear();
    r.lightPaths = 0;
    item.health = {};
    item.candidates.clear();
    if (estimator.reuseTileSize() > 0) {
        if (r.rect.area() > 0) estimator.estimateTile({r.rect, settings.seed, item.pass, r, item.health});
        return;
    }
    std::vector<Splat> splats;
    std::vector<PlaneValue> planeValues;
    uint64_t pixel = 0;
    const StrategyCallback onPath = [&](const StrategyPath& sp) {
        item.candidates.push_back(seedCandidate(scene, film, sp, pixel, uint64_t(item.pass)));
    };
    // One pixel sample; generic over the sampler so that its calls need no dispatch here.
    const auto estimatePixel = [&](int x, int y, auto& sampler) {
        const Vec2 raster = film.sampleRaster(x, y, sampler.next2D());
        splats.clear();
        planeValues.clear();
        PixelSample out{x, y, splats, planeValues, item.health, collect ? &onPath : nullptr};
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
                SobolSampler sampler(settings.seed, pixel, uint32_t(item.pass));
                estimatePixel(x, y, sampler);
            } else {
                IndependentSampler sampler = pixelSampler(settings.seed, item.pass, pixel);
                estimatePixel(x, y, sampler);
            }
        }
}

} // namespace

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
                   SampleFilm& film, const RunControl& control, SeedReservoir* seeds) {
    if (settings.spp < 0 || (settings.spp == 0 && !(settings.timeLimit > 0)))
        throw Error("give a positive sample count or a time limit");
    if (film.planes() != estimator.planes())
        throw Error("the film's planes are not the estimator's (make the film with estimator.planes())");
    const PixelRect window = film.window();
    const int reuse = estimator.reuseTileSize();
    if (reuse > 0 && settings.sampler != SamplerKind::Independent)
        throw Error("an estimator that works a tile at a time draws its own independent numbers: no other sampler");
    const TileGrid grid(window, reuse, settings.tileSize, settings.seed);
    const uint64_t tilesPerPass = grid.tilesPerPass();
    const uint64_t maxPasses = settings.spp > 0 ? uint64_t(settings.spp) : UINT64_MAX;
    // A run ends at a pass's end when a pixel's value needs the whole pass (samples credit neighbours), and
    // when it collects seeds: their normalization b = total x pixels / samples (sampling/seed_reservoir.h)
    // estimates the image's integral only if every pixel has as many samples.
    const bool wholePasses = estimator.creditsNeighbours() || seeds != nullptr;

    ParallelRun run(control);
    RenderStats stats;
    SnapshotSchedule schedule = settings.snapshots;
    const uint64_t totalSamples = settings.timeLimit > 0 ? 0 : maxPasses * window.area();
    uint64_t nextItem = 0;
    bool timeUp = false;
    run.ordered<WorkItem>(
        // Work items in a fixed order: pass by pass, tile by tile.
        [&](WorkItem& item) {
            const uint64_t pass = nextItem / tilesPerPass;
            if (run.stopped() || pass >= maxPasses) return false;
            // A time limit ends the run after the first pass: at the next work item, or at the next pass
            // boundary when whole passes are needed (above).
            if (settings.timeLimit > 0 && pass > 0 && (!wholePasses || nextItem % tilesPerPass == 0) &&
                run.elapsed() >= settings.timeLimit) {
                timeUp = true;
                return false;
            }
            item.index = nextItem;
            item.pass = int(pass);
            item.rect = grid.rect(nextItem % tilesPerPass, pass);
            ++nextItem;
            return true;
        },
        [&](WorkItem& item) { renderItem(scene, estimator, settings, film, seeds != nullptr, item); },
        // Merged in issue order.
        [&](WorkItem& item) {
            film.merge(item.result);
            if (seeds)
                for (const auto& c : item.candidates)
                    seeds->add(c);
            stats.samples += item.result.rect.area();
            stats.health.nonFinite += item.health.nonFinite;
            const bool passEnd = (item.index + 1) % tilesPerPass == 0;
            if (passEnd) {
                film.endPass();
                ++stats.passes;
            }
            double fraction = -1;
            if (totalSamples > 0)
                fraction = double(stats.samples) / double(totalSamples);
            else if (settings.timeLimit > 0)
                fraction = std::min(1.0, run.elapsed() / settings.timeLimit);
            RunProgress p = run.clock().progress("render", fraction, stats.samples, totalSamples);
            p.passesDone = stats.passes;
            if (passEnd && run.snapshots() && schedule.due(p.wallSeconds, double(stats.passes)))
                run.snapshot(
                    p, [&] { return film.toBuffer(); }, stats);
            run.report(p);
        });
    run.clock().close(stats);
    stats.interrupted = run.stopped() && !timeUp && uint64_t(stats.passes) < maxPasses;
    return stats;
}

} // namespace lt
