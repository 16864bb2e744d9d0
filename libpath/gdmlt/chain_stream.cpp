#include "gdmlt/chain_stream.h"

#include <chrono>

#include "gdmlt/chain_gradient.h"
#include "scene/scene.h"
#include "util/error.h"

namespace lt {

namespace {

// The four planes of chain_gradient.h, each a splat film read with the same b / N.
class PlaneFilms {
public:
    explicit PlaneFilms(const Scene& scene)
        : films_{SampleFilm(scene.camera), SampleFilm(scene.camera), SampleFilm(scene.camera),
                 SampleFilm(scene.camera)} {}

    [[nodiscard]] const PixelRect& window() const { return films_[0].window(); }
    [[nodiscard]] SampleFilm& direct() { return films_[3]; }

    void merge(const std::vector<ChainGradientSplats>& blocks, uint64_t mutations) {
        for (size_t p = 0; p < films_.size(); ++p) {
            std::vector<const std::vector<Splat>*> lists;
            for (const auto& b : blocks)
                lists.push_back(p == 0 ? &b.primal : p == 1 ? &b.dx : p == 2 ? &b.dy : &b.direct);
            films_[p].mergeSplats(lists, mutations);
        }
    }

    // The planes as formats/SPEC.md "Gradient-domain channels" names them, read with b.
    [[nodiscard]] file::Buffer buffer(double b) const {
        static const char* names[] = {"primal", "dx", "dy", "direct"};
        file::Buffer out;
        out.width = uint32_t(films_[0].width());
        out.height = uint32_t(films_[0].height());
        for (size_t p = 0; p < films_.size(); ++p) {
            std::vector<std::vector<float>> rgb = films_[p].developPlanes(b);
            for (size_t c = 0; c < 3; ++c) {
                out.channels.push_back(std::string(names[p]) + "." + "RGB"[c]);
                out.planes.push_back(std::move(rgb[c]));
            }
        }
        out.weight = double(films_[0].lightPaths());
        return out;
    }

private:
    std::array<SampleFilm, 4> films_;
};

} // namespace

ChainStreamStats gradientsFromStream(const Scene& scene, file::Reader& stream, const ChainStreamSettings& settings,
                                     file::Buffer& result, ShiftStatistics& shifts, const RunControl& control) {
    PlaneFilms films(scene);
    if (settings.direct.samples > 0) {
        RunControl direct = control;
        direct.progress = {}; // a second or so before the stream's rounds: no line of its own
        (void)renderDirectPart(scene, settings.paths, settings.direct, settings.seed, films.direct(), direct);
    }
    ParallelRun run(control);
    const double pixels = double(films.window().area());
    SnapshotSchedule schedule = settings.snapshots;
    ChainStreamStats stats;
    const bool afterChains = stream.regularFile(); // chain_stream.h: times
    constexpr size_t Block = 256;
    std::vector<ChainGradientSplats> blocks;
    std::atomic<uint64_t> nonFinite{0};
    for (;;) {
        if (run.stopped()) {
            stats.interrupted = true;
            break;
        }
        file::Chunk chunk = stream.next();
        if (std::holds_alternative<file::End>(chunk)) break;
        auto* round = std::get_if<file::ChainRound>(&chunk);
        if (!round) continue; // a dump's PATH batches or the tables: not estimates
        if (round->mutations < stats.mutations)
            throw Error(stream.name() + ": round " + std::to_string(stats.rounds + 1) + " counts " +
                        std::to_string(round->mutations) + " mutations, fewer than the round before (" +
                        std::to_string(stats.mutations) + ")");
        if (!(round->b > 0) || !std::isfinite(round->b))
            throw Error(stream.name() + ": round " + std::to_string(stats.rounds + 1) +
                        " has normalization b = " + std::to_string(round->b));
        const auto t0 = std::chrono::steady_clock::now();
        const size_t n = round->states.size();
        blocks.assign((n + Block - 1) / Block, {});
        run.forEach(
            blocks.size(),
            [&](uint64_t k) {
                for (size_t i = k * Block; i < std::min(n, (k + 1) * Block); ++i) {
                    try {
                        if (!addChainState(scene, films.window(), round->states[i], settings.shiftThreshold, blocks[k],
                                           &shifts))
                            ++nonFinite;
                    } catch (const Error& e) {
                        throw Error(stream.name() + ": round " + std::to_string(stats.rounds + 1) + ", state " +
                                    std::to_string(i) + ": " + e.what());
                    }
                }
            },
            [](uint64_t) {});
        run.execute([&] { films.merge(blocks, round->mutations - stats.mutations); });
        stats.ownSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        ++stats.rounds;
        stats.states += n;
        stats.mutations = round->mutations;
        stats.b = round->b;
        stats.bSamples = round->bSamples;
        stats.chainWallSeconds = round->wallSeconds;
        stats.chainCpuSeconds = round->cpuSeconds;
        RunProgress p = run.clock().progress("gradients", -1, stats.mutations, 0);
        if (afterChains) p.wallSeconds = stats.chainWallSeconds + stats.ownSeconds;
        p.cpuSeconds += stats.chainCpuSeconds;
        p.b = stats.b;
        if (run.snapshots() && schedule.due(p.wallSeconds, double(stats.mutations) / pixels))
            run.snapshot(
                p, [&] { return films.buffer(stats.b); }, stats);
        run.report(p);
    }
    if (stats.rounds == 0 && !stats.interrupted)
        throw Error(stream.name() + ": no chain states (CHST chunks); write the stream with lt-mutate --stream");
    run.clock().close(stats);
    if (afterChains) stats.wallSeconds = stats.chainWallSeconds + stats.ownSeconds;
    stats.cpuSeconds += stats.chainCpuSeconds;
    stats.health.nonFinite += nonFinite.load();
    result = films.buffer(stats.b);
    return stats;
}

} // namespace lt
