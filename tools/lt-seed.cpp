// lt-seed: render a scene with BDPT (or a path tracer) into a sample buffer, and optionally keep
// candidate seed paths and the normalization b for the Markov chains.
#include <cmath>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "common/info.h"
#include "common/interrupt.h"
#include "common/progress.h"
#include "common/run_output.h"
#include "common/scene_options.h"
#include "common/tool.h"
#include "formats/ltfile.h"
#include "sampling/render.h"
#include "sampling/seed_file.h"

using lt::tool::formatSeconds;

int main(int argc, char** argv) {
    CLI::App app{"lt-seed: render a Mitsuba scene with bidirectional path tracing (every (s,t) strategy, light "
                 "tracing included, MIS) or unidirectional path tracing with next-event estimation. Writes a "
                 "sample buffer (develop it with lt-image) and, with --paths, candidate seed paths and the "
                 "normalization b for lt-mutate. Same seed and sample count give a bit-identical file whatever the "
                 "thread count. Ctrl-C stops early and still writes a valid file.",
                 "lt-seed"};
    std::string scenePath, out, pathsOut, method = "bdpt", mis = "power", sampler = "independent", resolution,
                                          snapshotTimes, snapshotSamples;
    int spp = 0, maxDepth = -2, rrDepth = 0, threads = 0, tile = 32;
    double timeLimit = 0;
    uint64_t seed = 0;
    size_t maxPaths = 100000;
    bool quiet = false;
    std::vector<std::string> defines;
    app.add_option("SCENE", scenePath, "Mitsuba 0.5/0.6 scene (.xml)")->required();
    app.add_option("-o,--output", out, "output sample buffer (.lts), or - for stdout")->required();
    app.add_option("--method", method, "bdpt (default) or pt")->check(CLI::IsMember({"bdpt", "pt"}));
    app.add_option("--spp", spp, "samples per pixel (default: the scene's sampleCount; with --time, an upper bound)")
        ->check(lt::tool::PositiveNumber);
    app.add_option("--time", timeLimit, "render for this many seconds (at least one pass over the image; the last pass may cover part of it, except with --paths, whose normalization needs whole passes)")
        ->check(lt::tool::PositiveNumber);
    app.add_option("--max-depth", maxDepth,
                   "longest path in edges, Mitsuba's meaning: 1 = emitters seen directly, "
                   "-1 = unbounded (default: the scene's integrator maxDepth)");
    app.add_option("--rr-depth", rrDepth, "edges after which Russian roulette starts (default: the scene's rrDepth)")
        ->check(lt::tool::PositiveNumber);
    app.add_option("--mis", mis, "MIS heuristic: power (default) or balance")
        ->check(CLI::IsMember({"power", "balance"}));
    app.add_option("--sampler", sampler,
                   "random numbers of a pixel's samples: independent (default; PCG32) or sobol (padded Owen-scrambled "
                   "Sobol' points, Burley 2020: each 1D and 2D sample of a path is stratified over the pixel's "
                   "samples, which lowers the noise of smooth regions, most at 2^k samples per pixel; unbiased)")
        ->check(CLI::IsMember({"independent", "sobol"}));
    app.add_option("--threads", threads, "worker threads (default: all cores)")->check(lt::tool::ThreadCount);
    app.add_option("--seed", seed, "random seed (default 0)");
    app.add_option("--resolution", resolution, "film size WxH, overriding the scene's (keeps the horizontal fov)");
    app.add_option("--paths", pathsOut, "also write candidate seed paths (.ltp), or - for stdout");
    app.add_option("--max-paths", maxPaths,
                   "seed paths to keep: independent draws in proportion to weight (default 100000)")
        ->check(lt::tool::PositiveNumber);
    app.add_option("--snapshots", snapshotTimes,
                   "write progress snapshots (SNAP chunks, for lt-error): 'doubling' (1, 2, 4 ... s), "
                   "'doubling:START', or a list of seconds '5,10,30'; taken at the end of a pass over the image");
    app.add_option("--snapshot-samples", snapshotSamples, "write snapshots at these samples per pixel, e.g. '1,4,16'");
    app.add_option("--tile", tile, "tile size in pixels (default 32; changes the sample order, not the estimate)")
        ->check(lt::tool::PositiveNumber);
    app.add_option("-D,--define", defines, "scene parameter NAME=VALUE, overriding the scene's <default>")
        ->type_name("NAME=VALUE");
    bool strict = false;
    lt::tool::addStrictFlag(app, strict);
    app.add_flag("-q,--quiet", quiet, "no progress output");

    return lt::tool::run(app, argc, argv, [&] {
        if (out == "-" && pathsOut == "-") throw lt::Error("only one of -o and --paths can be stdout");
        if (pathsOut.empty() && app.count("--max-paths")) throw lt::Error("--max-paths needs --paths");
        if (method == "pt" && !pathsOut.empty())
            throw lt::Error("--paths needs --method bdpt (seed paths are BDPT strategies)");
        auto scene = lt::tool::loadSceneWithOptions("lt-seed", scenePath, defines, resolution, strict, quiet);

        lt::RenderSettings rs;
        rs.paths.maxDepth = maxDepth != -2 ? maxDepth : scene->integrator.maxDepth;
        rs.paths.rrDepth = rrDepth > 0 ? rrDepth : scene->integrator.rrDepth;
        rs.paths.mis = mis == "balance" ? lt::MisHeuristic::Balance : lt::MisHeuristic::Power;
        if (rs.paths.maxDepth == 0 || rs.paths.maxDepth < -1)
            throw lt::Error("--max-depth must be -1 (unbounded) or at least 1");
        rs.spp = spp > 0 ? spp : (timeLimit > 0 ? 0 : scene->integrator.sampleCount);
        rs.timeLimit = timeLimit;
        rs.threads = threads;
        rs.seed = seed;
        rs.sampler = sampler == "sobol" ? lt::SamplerKind::Sobol : lt::SamplerKind::Independent;
        rs.tileSize = tile;
        if (!snapshotTimes.empty() && !snapshotSamples.empty())
            throw lt::Error("give --snapshots or --snapshot-samples, not both");
        if (!snapshotTimes.empty()) rs.snapshots = lt::SnapshotSchedule::parseTimes(snapshotTimes);
        if (!snapshotSamples.empty()) rs.snapshots = lt::SnapshotSchedule::parseSamples(snapshotSamples);

        // Open the outputs before the work, so a bad path fails now and not after an hour of rendering.
        nlohmann::json params = {{"snapshots", snapshotTimes.empty() ? snapshotSamples : snapshotTimes},
                                 {"method", method},
                                 {"spp", rs.spp},
                                 {"time_limit", timeLimit},
                                 {"max_depth", rs.paths.maxDepth},
                                 {"rr_depth", rs.paths.rrDepth},
                                 {"mis", mis},
                                 {"seed", seed},
                                 {"sampler", sampler},
                                 {"tile", tile},
                                 {"resolution", {scene->camera.film().width, scene->camera.film().height}},
                                 {"filter", scene->camera.film().filter.name()}};
        lt::file::Writer writer(out, lt::file::FileKind::Buffer,
                                lt::tool::makeInfo("lt-seed", argc, argv, params, scene.get()));
        std::optional<lt::file::Writer> pathWriter;
        std::optional<lt::SeedReservoir> reservoir;
        if (!pathsOut.empty()) {
            nlohmann::json pparams = params;
            pparams["max_paths"] = maxPaths;
            pparams["selection"] = "independent draws with replacement, each proportional to weight over all "
                                   "candidates (K weighted reservoirs of size one): pick uniformly among them";
            pparams["b_convention"] = "STAT normalization.b = integral over the sensor's raster positions of (crop "
                                      "pixels) x luminance(f), the Markov chains' normalization; camera-strategy "
                                      "weights are divided by the sum of the pixel filters at their raster position";
            pathWriter.emplace(pathsOut, lt::file::FileKind::Paths,
                               lt::tool::makeInfo("lt-seed", argc, argv, pparams, scene.get()));
            reservoir.emplace(maxPaths, seed ^ 0x9e3779b97f4a7c15ULL);
        }

        lt::tool::installInterruptHandler();
        lt::SampleFilm film(scene->camera);
        lt::tool::Progress progress("lt-seed", quiet);
        const auto estimator = lt::makePixelEstimator(
            method == "pt" ? lt::PixelMethod::PathTracing : lt::PixelMethod::Bdpt, *scene, rs.paths);
        const auto stats = lt::render(
            *scene, *estimator, rs, film, lt::tool::runProgress(progress, double(film.width()) * film.height(), "spp"),
            &lt::tool::stopRequested(), reservoir ? &*reservoir : nullptr, lt::tool::snapshotWriter(writer));
        progress.finish();

        const double pixels = double(film.width()) * double(film.height());
        const double samplesPerPixel = double(stats.samples) / pixels;
        writer.writeBuffer(film.toBuffer());
        writer.writeStats(lt::tool::renderRunTable(stats, pixels));
        writer.finish();

        if (pathWriter) {
            const auto written = lt::writeSeedFile(*pathWriter, *reservoir, stats.samples, pixels);
            if (!quiet)
                std::cerr << "lt-seed: b = " << written.b << " (" << reservoir->candidates() << " candidates, "
                          << written.kept << " kept) -> " << pathWriter->name() << '\n';
        }
        if (!quiet) {
            std::cerr << "lt-seed: " << (stats.interrupted ? "interrupted after " : "") << samplesPerPixel << " spp in "
                      << formatSeconds(stats.wallSeconds) << " (" << std::setprecision(3)
                      << double(stats.samples) / stats.wallSeconds / 1e3 << "k samples/s, "
                      << double(stats.rays) / stats.wallSeconds / 1e6 << "M rays/s) -> " << writer.name();
            if (stats.health.nonFinite) std::cerr << " (" << stats.health.nonFinite << " non-finite samples dropped)";
            std::cerr << '\n';
        }
        return stats.interrupted ? lt::tool::interruptedExitCode() : 0;
    });
}
