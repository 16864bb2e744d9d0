// lt-gradient: gradient-domain rendering of a scene: the primal image and its forward-difference gradients
// from shifted paths (G-PT, or gradient-domain path reusing), for lt-reconstruct to turn into the image.
#include <chrono>
#include <iomanip>
#include <iostream>

#include "common/info.h"
#include "common/interrupt.h"
#include "common/progress.h"
#include "common/run_output.h"
#include "common/scene_options.h"
#include "common/tool.h"
#include "formats/ltfile.h"
#include "mcmc/chain_stream.h"
#include "gradient/gradient_path_tracer.h"
#include "gradient/path_reusing.h"
#include "sampling/render.h"

using lt::tool::formatSeconds;

namespace {

struct StreamOptions {
    std::string scenePath, out, stream, resolution, snapshotTimes;
    std::vector<std::string> defines;
    double shiftThreshold;
    int threads;
    bool strict, quiet;
};

// --from-paths: the gradient stage of gradient-domain MLT (mcmc/chain_stream.h).
int fromChainStream(const CLI::App&, int argc, char** argv, const StreamOptions& o) {
    const auto start = std::chrono::steady_clock::now();
    auto scene = lt::tool::loadSceneWithOptions("lt-gradient", o.scenePath, o.defines, o.resolution, o.strict, o.quiet);
    if (scene->camera.hasAperture())
        throw lt::Error(o.scenePath + ": the chain-state stream holds no lens points, and this scene's thinlens camera "
                                      "needs them (the gradient stage works with pinhole cameras)");
    lt::file::Reader stream(o.stream, lt::file::FileKind::Paths);
    lt::file::checkSceneHash(stream.info(), scene->contentHash, stream.name(), o.scenePath);
    const auto& made = stream.info().value("parameters", nlohmann::json::object());
    const lt::Film& film = scene->camera.film();
    if (made.contains("resolution") && made["resolution"] != nlohmann::json{film.width, film.height})
        throw lt::Error(stream.name() + ": made at resolution " + made["resolution"].dump() + " but the film is " +
                        std::to_string(film.width) + "x" + std::to_string(film.height) +
                        " (give the same --resolution to both tools)");
    lt::ChainStreamSettings settings;
    settings.shiftThreshold = o.shiftThreshold;
    settings.threads = o.threads;
    settings.start = start;
    if (!o.snapshotTimes.empty()) settings.snapshots = lt::SnapshotSchedule::parseTimes(o.snapshotTimes);
    nlohmann::json params = {{"method", "chain-states"},
                             {"stream", o.stream},
                             {"stream_producer", stream.info().value("producer", "")},
                             {"chain_parameters", made},
                             {"shift_threshold", o.shiftThreshold},
                             {"weights", "pairs of a state and its shift, g*(x) / (g*(x) + g*(Tx) |T'|) with g* = "
                                         "lum f, each over the chain's density b f*(x) / N"},
                             {"snapshots", o.snapshotTimes},
                             {"resolution", {film.width, film.height}},
                             {"filter", film.filter.name()}};
    lt::file::Writer writer(o.out, lt::file::FileKind::Buffer,
                            lt::tool::makeInfo("lt-gradient", argc, argv, params, scene.get()));
    lt::tool::installInterruptHandler();
    lt::tool::Progress progress("lt-gradient", o.quiet);
    const double pixels = double(film.cropWidth) * double(film.cropHeight);
    lt::ShiftStatistics shifts;
    lt::file::Buffer result;
    const auto stats = lt::gradientsFromStream(*scene, stream, settings, result, shifts,
                                               lt::tool::runProgress(progress, pixels, "mutations/pixel"),
                                               lt::tool::snapshotWriter(writer), &lt::tool::stopRequested());
    progress.finish();
    writer.writeBuffer(result);
    writer.writeStats(lt::file::valueTable("run", {{"rounds", double(stats.rounds)},
                                                   {"states", double(stats.states)},
                                                   {"mutations", double(stats.mutations)},
                                                   {"wall_seconds", stats.wallSeconds},
                                                   {"cpu_seconds", stats.cpuSeconds},
                                                   {"chain_wall_seconds", stats.chainWallSeconds},
                                                   {"own_seconds", stats.ownSeconds},
                                                   {"rays", double(stats.rays)},
                                                   {"nonfinite_dropped", double(stats.health.nonFinite)},
                                                   {"interrupted", stats.interrupted ? 1.0 : 0.0},
                                                   {"snapshots", double(stats.snapshots)},
                                                   {"snapshot_seconds", stats.snapshotSeconds}}));
    writer.writeStats(lt::file::valueTable("normalization", {{"b", stats.b}, {"b_samples", double(stats.bSamples)}}));
    writer.writeStats(shifts.table());
    writer.finish();
    if (!o.quiet) {
        const double n = std::max<double>(1, double(shifts.shifts));
        std::cerr << "lt-gradient: " << (stats.interrupted ? "interrupted after " : "") << stats.states
                  << " chain states of " << stats.rounds << " rounds (" << double(stats.mutations) / pixels
                  << " mutations/pixel) in " << formatSeconds(stats.ownSeconds) << "; " << double(shifts.shifts)
                  << " shifts: " << std::setprecision(3)
                  << 100 * double(shifts.causes[size_t(lt::ShiftCause::Reconnected)]) / n << "% reconnected, "
                  << 100 * double(shifts.causes[size_t(lt::ShiftCause::Mismatch)]) / n << "% mismatched, "
                  << 100 * double(shifts.causes[size_t(lt::ShiftCause::Occluded)]) / n << "% occluded";
        if (stats.health.nonFinite) std::cerr << " (" << stats.health.nonFinite << " non-finite states dropped)";
        std::cerr << " -> " << writer.name() << '\n';
    }
    return stats.interrupted ? lt::tool::interruptedExitCode() : 0;
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"lt-gradient: render a Mitsuba scene in the gradient domain. Base paths are traced as by a path "
                 "tracer with next-event estimation and shifted to other pixels (reconnection at the first pair of "
                 "rough vertices, half-vector copy through smooth ones). --method gpt shifts every path to its four "
                 "neighbours (gradient-domain path tracing); --method gdpr reuses every path in all pixels of its "
                 "tile (gradient-domain path reusing). Writes the planes primal, dx, dy and direct as lt-reconstruct "
                 "reads them, and per pixel the variance of one pass's value of each (NAME.var, luminance): "
                 "lt-gradient S -o - | "
                 "lt-reconstruct - -o image.exr. With --from-paths it is the gradient stage of gradient-domain MLT "
                 "instead: the states of lt-mutate's chains (lt-mutate S --stream -) are shifted to their four "
                 "neighbours and weighed as draws of the chains' density. Same seed and sample count give a "
                 "bit-identical file whatever the thread count; Ctrl-C stops after the current tiles (or round) and "
                 "still writes a valid file.",
                 "lt-gradient"};
    std::string scenePath, out, method = "gdpr", resolution, snapshotTimes, snapshotSamples, fromPaths;
    int spp = 0, maxDepth = -2, rrDepth = 0, threads = 0;
    double timeLimit = 0;
    uint64_t seed = 0;
    lt::GradientSettings gs;
    bool quiet = false;
    std::vector<std::string> defines;
    app.add_option("SCENE", scenePath, "Mitsuba 0.5/0.6 scene (.xml)")->required();
    app.add_option("-o,--output", out, "output buffer file (.lts), or - for stdout")->required();
    app.add_option("--method", method,
                   "gdpr (default: gradient-domain path reusing) or gpt (gradient-domain path tracing)")
        ->check(CLI::IsMember({"gpt", "gdpr"}));
    app.add_option("--from-paths", fromPaths,
                   "the chain-state stream of lt-mutate --stream (a file, or - for stdin): estimate primal, dx, dy and "
                   "direct from the chains' states (gradient-domain MLT) instead of tracing base paths; the options "
                   "of the path tracers (--method, --spp, --time, --tile, --max-depth, --rr-*, --seed) do not apply");
    app.add_option("--spp", spp,
                   "samples per pixel: base paths per pixel (default: the scene's sampleCount; with --time, an upper "
                   "bound)")
        ->check(lt::tool::PositiveNumber);
    app.add_option("--time", timeLimit, "render for this many seconds (at least one pass over the image; gpt ends at the end of a pass, gdpr after the tile under way)")
        ->check(lt::tool::PositiveNumber);
    app.add_option("--tile", gs.tile,
                   "gdpr: tile size T; every base path is reused by the (T+1) x (T+1) pixels around its tile (default "
                   "6, the paper's; 6 to 8 are the most efficient there)")
        ->check(CLI::Range(1, 64));
    app.add_option("--max-depth", maxDepth,
                   "longest path in edges, Mitsuba's meaning (default: the scene's integrator maxDepth; -1 unbounded)");
    app.add_option("--rr-depth", rrDepth,
                   "edges after which base paths continue by Russian roulette (default: the scene's)")
        ->check(lt::tool::PositiveNumber);
    app.add_option(
           "--shift-threshold", gs.shiftThreshold,
           "Beckmann roughness at or below which a vertex is followed by its half vector instead of reconnected "
           "(default 0.001, as the public G-PT code)")
        ->check(lt::tool::NonNegativeNumber);
    app.add_option("--rr-delta", gs.rrDelta,
                   "gdpr: base paths survive with probability min(1, max(q_min, luminance / delta)) (default 0.1)")
        ->check(lt::tool::PositiveNumber);
    app.add_option("--rr-min", gs.rrMin, "gdpr: q_min, the least survival probability (default 0.1; 0 is biased)")
        ->check(CLI::Range(0.0, 1.0));
    app.add_option("--threads", threads, "worker threads (default: all cores)")->check(lt::tool::ThreadCount);
    app.add_option("--seed", seed, "random seed (default 0)");
    app.add_option("--resolution", resolution, "film size WxH, overriding the scene's (keeps the horizontal fov)");
    app.add_option("--snapshots", snapshotTimes,
                   "write progress snapshots (SNAP chunks with primal, dx, dy, direct; lt-reconstruct reconstructs "
                   "each, and lt-error measures its output): 'doubling', 'doubling:START', or seconds '5,10,30'");
    app.add_option("--snapshot-samples", snapshotSamples, "write snapshots at these samples per pixel, e.g. '1,4,16'");
    app.add_option("-D,--define", defines, "scene parameter NAME=VALUE, overriding the scene's <default>")
        ->type_name("NAME=VALUE");
    bool strict = false;
    lt::tool::addStrictFlag(app, strict);
    app.add_flag("-q,--quiet", quiet, "no progress output");

    return lt::tool::run(app, argc, argv, [&] {
        if (!fromPaths.empty()) {
            for (const char* o : {"--method", "--spp", "--time", "--tile", "--max-depth", "--rr-depth", "--rr-delta",
                                  "--rr-min", "--seed", "--snapshot-samples"})
                if (app.count(o)) throw lt::Error(std::string(o) + " is not an option of --from-paths");
            return fromChainStream(app, argc, argv,
                                   {scenePath, out, fromPaths, resolution, snapshotTimes, defines, gs.shiftThreshold,
                                    threads, strict, quiet});
        }
        const bool gpt = method == "gpt";
        if (gpt && (app.count("--tile") || app.count("--rr-delta") || app.count("--rr-min")))
            throw lt::Error("--tile, --rr-delta and --rr-min are options of --method gdpr");
        if (!gpt && gs.rrMin == 0)
            std::cerr << "lt-gradient: warning: --rr-min 0 is biased (base paths that carry nothing never survive, "
                         "though their shifts to other pixels would)\n";
        auto scene = lt::tool::loadSceneWithOptions("lt-gradient", scenePath, defines, resolution, strict, quiet);
        gs.paths.maxDepth = maxDepth != -2 ? maxDepth : scene->integrator.maxDepth;
        gs.paths.rrDepth = rrDepth > 0 ? rrDepth : scene->integrator.rrDepth;
        if (gs.paths.maxDepth == 0 || gs.paths.maxDepth < -1)
            throw lt::Error("--max-depth must be -1 (unbounded) or at least 1");
        lt::RenderSettings rs;
        rs.paths = gs.paths;
        rs.spp = spp > 0 ? spp : (timeLimit > 0 ? 0 : scene->integrator.sampleCount);
        rs.timeLimit = timeLimit;
        rs.threads = threads;
        rs.seed = seed;
        if (!snapshotTimes.empty() && !snapshotSamples.empty())
            throw lt::Error("give --snapshots or --snapshot-samples, not both");
        if (!snapshotTimes.empty()) rs.snapshots = lt::SnapshotSchedule::parseTimes(snapshotTimes);
        if (!snapshotSamples.empty()) rs.snapshots = lt::SnapshotSchedule::parseSamples(snapshotSamples);

        nlohmann::json params = {{"method", method},
                                 {"spp", rs.spp},
                                 {"time_limit", timeLimit},
                                 {"max_depth", gs.paths.maxDepth},
                                 {"rr_depth", gs.paths.rrDepth},
                                 {"shift_threshold", gs.shiftThreshold},
                                 {"mis", "balance over the pixels' techniques, light and BSDF sample within each"},
                                 {"seed", seed},
                                 {"snapshots", snapshotTimes.empty() ? snapshotSamples : snapshotTimes},
                                 {"resolution", {scene->camera.film().width, scene->camera.film().height}},
                                 {"filter", scene->camera.film().filter.name()}};
        if (!gpt) {
            params["tile"] = gs.tile;
            params["rr_delta"] = gs.rrDelta;
            params["rr_min"] = gs.rrMin;
        }
        lt::file::Writer writer(out, lt::file::FileKind::Buffer,
                                lt::tool::makeInfo("lt-gradient", argc, argv, params, scene.get()));

        std::unique_ptr<lt::PixelEstimator> estimator;
        const lt::ShiftStatistics* shiftStats = nullptr;
        if (gpt) {
            auto e = std::make_unique<lt::GradientPathTracer>(*scene, gs);
            shiftStats = &e->statistics();
            estimator = std::move(e);
        } else {
            auto e = std::make_unique<lt::PathReusing>(*scene, gs);
            shiftStats = &e->statistics();
            estimator = std::move(e);
        }
        lt::tool::installInterruptHandler();
        lt::SampleFilm film(scene->camera, estimator->planes());
        lt::tool::Progress progress("lt-gradient", quiet);
        const auto stats = lt::render(*scene, *estimator, rs, film,
                                      lt::tool::runProgress(progress, double(film.width()) * film.height(), "spp"),
                                      &lt::tool::stopRequested(), nullptr, lt::tool::snapshotWriter(writer));
        progress.finish();

        const double pixels = double(film.width()) * double(film.height());
        const double samplesPerPixel = double(stats.samples) / pixels;
        writer.writeBuffer(film.toBuffer());
        writer.writeStats(lt::tool::renderRunTable(stats, pixels));
        writer.writeStats(shiftStats->table());
        writer.finish();
        if (!quiet) {
            const auto& s = *shiftStats;
            const double shifts = std::max<double>(1, double(s.shifts));
            std::cerr << "lt-gradient: " << method << ", " << (stats.interrupted ? "interrupted after " : "")
                      << samplesPerPixel << " spp in " << formatSeconds(stats.wallSeconds) << " ("
                      << std::setprecision(3) << double(stats.rays) / stats.wallSeconds / 1e6 << "M rays/s); "
                      << double(s.shifts)
                      << " shifts: " << 100 * double(s.causes[size_t(lt::ShiftCause::Reconnected)]) / shifts
                      << "% reconnected, " << 100 * double(s.causes[size_t(lt::ShiftCause::Mismatch)]) / shifts
                      << "% mismatched, " << 100 * double(s.causes[size_t(lt::ShiftCause::Occluded)]) / shifts
                      << "% occluded";
            if (!gpt)
                std::cerr << "; " << 100 * double(s.rrSurvived) / std::max<double>(1, double(s.rrTested))
                          << "% of base paths survived Russian roulette";
            if (stats.health.nonFinite) std::cerr << " (" << stats.health.nonFinite << " non-finite samples dropped)";
            std::cerr << " -> " << writer.name() << '\n';
        }
        return stats.interrupted ? lt::tool::interruptedExitCode() : 0;
    });
}
