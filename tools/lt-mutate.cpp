// lt-mutate: Markov-chain Monte Carlo rendering: path-space MLT (Veach and Guibas 1997) started from
// seed paths, Kelemen's primary-sample-space MLT and multiplexed MLT over lt's BDPT, with per-strategy
// statistics, snapshots and Ctrl-C.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <iostream>

#include "common/info.h"
#include "common/interrupt.h"
#include "common/progress.h"
#include "common/chain_stream_writer.h"
#include "common/run_output.h"
#include "mcmc/chain_gradient.h"
#include "common/scene_options.h"
#include "common/tool.h"
#include "formats/ltfile.h"
#include "mcmc/path_space_chains.h"
#include "mcmc/primary_space_chains.h"
#include "mcmc/mutation_selection.h"
#include "mcmc/mutations/manifold_perturbation.h"

using lt::tool::formatSeconds;

// Proposals of the manifold perturbation's pre-run (ME App. A1; Mitsuba averages its first 50 000
// samples, as here): a fraction of a second.
constexpr size_t NormalChangePreRun = 50000;

int main(int argc, char** argv) {
    CLI::App app{"lt-mutate: render a Mitsuba scene with Markov chains. --space path (default) is Veach-Guibas "
                 "path-space MLT: chains of whole paths started from seed paths (a file from lt-seed --paths, or a "
                 "BDPT start-up of its own), mutated by --strategies. --space primary is Kelemen's primary-sample-"
                 "space MLT over BDPT (every (s,t) strategy of a sample accepted or rejected together); --space "
                 "multiplexed is Hachisuka's multiplexed MLT (one (s,t) strategy per sample, chosen by the chain; the "
                 "path length is part of the state, changed by large steps). Chains start from a start-up run that "
                 "first estimates the normalization b and picks their first states in proportion to the target "
                 "(start-up bias removal); b keeps being refined during the run (large steps, --refine-b) and the "
                 "image is scaled by it at every snapshot and at the end. Same seed and "
                 "mutation count give a bit-identical image whatever the thread count. Prints per-strategy "
                 "statistics and stores them in the output. Ctrl-C stops early and still writes a valid file.",
                 "lt-mutate"};
    std::string scenePath, seedsPath, out, space = "path", resolution, snapshotTimes, snapshotMutations,
                                           strategies = "auto", dumpPaths, streamPath;
    uint64_t mutations = 0, seed = 0, startupSamples = 0;
    double timeLimit = 0, mutationsPerPixel = 0, largeStep = 0.3,
           startupError = lt::PrimarySpaceSettings().startupError, refineB = 1.0 / 16, lambda = 50, hsltGamma = 0.1,
           hsltStratify = 0.02;
    int chains = 256, threads = 0, maxDepth = -2, unbounded = 12, round = 64;
    size_t dumpEvery = 0;
    bool quiet = false;
    std::string hsltJumps = "off", target = "luminance";
    double gradientAlpha = 0.2, shiftThreshold = 0.001;
    std::vector<double> portalRange = {1.0 / 256, 1.0 / 16};
    std::vector<std::string> defines;
    app.add_option("SCENE", scenePath, "Mitsuba 0.5/0.6 scene (.xml)")->required();
    app.add_option("SEEDS", seedsPath,
                   "seed paths from lt-seed --paths (.ltp, or - for stdin) for --space path; "
                   "without it the tool seeds itself with BDPT");
    app.add_option("-o,--output", out, "output sample buffer (.lts), or - for stdout")->required();
    app.add_option("--space", space,
                   "path (default; Veach-Guibas MLT), primary (Kelemen PSSMLT) or multiplexed "
                   "(Hachisuka MMLT)")
        ->check(CLI::IsMember({"primary", "multiplexed", "path"}));
    app.add_option("--strategies", strategies, lt::mutationsHelp());
    app.add_option("--lambda", lambda,
                   "manifold perturbation: the direction lobe's peak as lambda^2 times the BSDF's sampling density "
                   "(default 50; Jakob & Marschner suggest 50-500: larger takes smaller steps)")
        ->check(lt::tool::PositiveNumber);
    app.add_option("--hslt-gamma", hsltGamma,
                   "half-vector mutation: its step at each vertex as gamma times the Beckmann lobe's standard "
                   "deviation (default 0.1, HSLT's value for all its images; in (0, 1])")
        ->check(CLI::Range(0.0, 1.0));
    app.add_option("--hslt-stratify", hsltStratify,
                   "half-vector mutation: the image-plane step limiting it, a fraction of the image (default 0.02, "
                   "HSLT's; 0 turns the limit off)")
        ->check(CLI::Range(0.0, 1.0));
    app.add_option("--hslt-jumps", hsltJumps,
                   "half-vector mutation: where a walk fails, propose its first prediction projected onto whatever "
                   "it hits (HSLT's jumps between subspaces; off by default: on glossy-rings they left chains stuck "
                   "in the corners where a ring touches the ground, relMSE 4.8 against 0.37 at 120 s)")
        ->check(CLI::IsMember({"on", "off"}));
    app.add_option("--portal-range", portalRange,
                   "portal perturbation: the smallest and largest turn of the edge about its crossing, in radians "
                   "(default 0.00390625,0.0625: 2^-8 and 2^-4, Otsu et al.'s values)")
        ->expected(2)
        ->delimiter(',');
    app.add_option("--mutations", mutations, "total mutations over all chains")->check(lt::tool::PositiveNumber);
    app.add_option("--mutations-per-pixel", mutationsPerPixel, "total mutations as a multiple of the pixel count")
        ->check(lt::tool::PositiveNumber);
    app.add_option("--time", timeLimit, "run for this many seconds, start-up included")->check(lt::tool::PositiveNumber);
    app.add_option("--chains", chains, "independent chains (default 256, whatever the thread count)")
        ->check(lt::tool::PositiveNumber);
    app.add_option("--threads", threads, "worker threads (default: all cores)")->check(lt::tool::ThreadCount);
    app.add_option("--seed", seed, "random seed (default 0)");
    app.add_option("--max-depth", maxDepth,
                   "longest path in edges, Mitsuba's meaning (default: the scene's "
                   "integrator maxDepth)");
    app.add_option("--max-length-unbounded", unbounded,
                   "multiplexed: the path-length bound used when the max depth is -1 (default 12)")
        ->check(lt::tool::PositiveNumber);
    app.add_option("--large-step", largeStep, "probability of a large step (default 0.3, Mitsuba's)")
        ->check(CLI::Range(0.0, 1.0));
    app.add_option("--startup-samples", startupSamples,
                   "independent samples that first estimate b and seed the chains, at most (default 100000; "
                   "multiplexed: per path length on average, default 20000, the same work for each length; path "
                   "space without a seed file: BDPT samples, all of them). The primary spaces spend 1/8 of it "
                   "evenly, then rounds with a quarter evenly and the rest where b's spread is (Neyman allocation "
                   "over the lengths), and stop once b is known to --startup-error")
        ->check(lt::tool::PositiveNumber);
    app.add_option("--startup-error", startupError,
                   "primary spaces: the start-up stops once b's relative standard error is at most this (default "
                   "0.005; 0 spends all of --startup-samples). The large steps refine b during the run")
        ->check(CLI::Range(0.0, 1.0));
    app.add_option("--refine-b", refineB,
                   "path space: independent BDPT samples per mutation that keep refining b during the run (default "
                   "0.0625, one per 16 mutations of a chain; 0 keeps the seed run's b). The primary spaces refine b "
                   "with their large steps")
        ->check(CLI::Range(0.0, 1.0));
    app.add_option("--round", round,
                   "mutations per chain between merges (default 64; sets the granularity of "
                   "snapshots, not the estimate)")
        ->check(lt::tool::PositiveNumber);
    app.add_option("--resolution", resolution, "film size WxH, overriding the scene's (keeps the horizontal fov)");
    app.add_option("--snapshots", snapshotTimes,
                   "write progress snapshots for lt-error: 'doubling', 'doubling:START' or seconds '5,10,30'");
    app.add_option("--snapshot-mutations", snapshotMutations,
                   "write snapshots at these mutations per pixel, e.g. '1,4,16'");
    app.add_option("--dump-paths", dumpPaths,
                   "path space: write every K-th state of every chain to a paths file (.ltp, or - for stdout) for "
                   "trace plots and lt-inspect; rngStream = chain, rngOffset = mutation");
    app.add_option("--dump-every", dumpEvery, "with --dump-paths: K (mutations of a chain between dumped states)")
        ->check(lt::tool::PositiveNumber);
    app.add_option(
           "--target", target,
           "path space: the function the chains sample: luminance (default; MLT) or gradient (gradient-domain "
           "MLT, Lehtinen et al. 2013: the luminance of the differences to the four neighbouring pixels' "
           "shifted paths plus --gradient-alpha times the path's own; for --stream and lt-gradient "
           "--from-paths). b stays the integral of luminance; the image is read with b N / (sum of the credits x "
           "lum f / f*)")
        ->check(CLI::IsMember({"luminance", "gradient"}));
    app.add_option("--gradient-alpha", gradientAlpha,
                   "--target gradient: weight of the path's own luminance in the target (default 0.2)")
        ->check(lt::tool::PositiveNumber);
    app.add_option("--shift-threshold", shiftThreshold,
                   "--target gradient: Beckmann roughness at or below which the shift follows a vertex's half vector "
                   "instead of reconnecting (default 0.001, as lt-gradient)")
        ->check(lt::tool::NonNegativeNumber);
    app.add_option("--stream", streamPath,
                   "path space: write the chain-state stream to a paths file (.ltp, or - for stdout): every state the "
                   "image credited, with its credit, f, f* and each round's mutation count and b, for lt-gradient "
                   "--from-paths (CHST chunks, formats/SPEC.md)");
    app.add_option("-D,--define", defines, "scene parameter NAME=VALUE, overriding the scene's <default>")
        ->type_name("NAME=VALUE");
    bool strict = false;
    lt::tool::addStrictFlag(app, strict);
    app.add_flag("-q,--quiet", quiet, "no progress output");

    return lt::tool::run(app, argc, argv, [&] {
        if (!dumpPaths.empty() && space != "path") throw lt::Error("--dump-paths needs --space path");
        if (dumpPaths.empty() != (dumpEvery == 0)) throw lt::Error("--dump-paths and --dump-every go together");
        if (!streamPath.empty() && space != "path") throw lt::Error("--stream needs --space path");
        if (target != "luminance" && space != "path") throw lt::Error("--target " + target + " needs --space path");
        if (target != "gradient" && (app.count("--gradient-alpha") || app.count("--shift-threshold")))
            throw lt::Error("--gradient-alpha and --shift-threshold are options of --target gradient");
        if (int(out == "-") + int(dumpPaths == "-") + int(streamPath == "-") > 1)
            throw lt::Error("only one of -o, --dump-paths and --stream can be stdout");
        if (!streamPath.empty() && (streamPath == out || streamPath == dumpPaths))
            throw lt::Error("--stream needs a file of its own");
        lt::requireChainMemory(chains); // before the scene and the start-up, which keeps 4 seeds per chain
        if (space != "path" && app.count("--strategies") && strategies != "auto")
            throw lt::Error("--strategies selects path-space mutations; --space " + space +
                            " has its own (large and small steps, --large-step)");
        if (space != "path" && app.count("--lambda")) throw lt::Error("--lambda is for --space path");
        if (space != "path" && (app.count("--hslt-gamma") || app.count("--hslt-stratify") || app.count("--hslt-jumps")))
            throw lt::Error("--hslt-gamma, --hslt-stratify and --hslt-jumps are for --space path");
        // CLI11's range checks let NaN through; refuse it before the seeding.
        if (!(hsltGamma > 0)) throw lt::Error("--hslt-gamma must lie in (0, 1], got " + std::to_string(hsltGamma));
        if (!(hsltStratify >= 0))
            throw lt::Error("--hslt-stratify must lie in [0, 1], got " + std::to_string(hsltStratify));
        if (space != "path" && app.count("--portal-range")) throw lt::Error("--portal-range is for --space path");
        if (!(portalRange[0] > 0 && portalRange[0] < portalRange[1] && portalRange[1] < lt::Pi / 2))
            throw lt::Error("--portal-range: need 0 < MIN < MAX < pi/2 radians, got " + std::to_string(portalRange[0]) +
                            "," + std::to_string(portalRange[1]));
        if (space == "path" && (app.count("--large-step") || app.count("--max-length-unbounded")))
            throw lt::Error("--large-step and --max-length-unbounded are for --space primary and multiplexed");
        if (space != "path" && app.count("--refine-b"))
            throw lt::Error("--refine-b is for --space path; the primary spaces refine b with their large steps");
        const int bounds = (mutations > 0) + (mutationsPerPixel > 0);
        if (bounds > 1) throw lt::Error("give --mutations or --mutations-per-pixel, not both");
        if (bounds == 0 && !(timeLimit > 0)) throw lt::Error("give --mutations, --mutations-per-pixel or --time");
        if (!snapshotTimes.empty() && !snapshotMutations.empty())
            throw lt::Error("give --snapshots or --snapshot-mutations, not both");
        if (startupSamples == 0) startupSamples = space == "multiplexed" ? 20000 : 100000;
        auto scene = lt::tool::loadSceneWithOptions("lt-mutate", scenePath, defines, resolution, strict, quiet);
        if (!streamPath.empty() && scene->camera.hasAperture())
            throw lt::Error(scenePath + ": --stream writes no lens points yet, and this scene's thinlens camera needs "
                                        "them (the gradient stage works with pinhole cameras)");

        // Seeds are path-space states: path-space chains start from them; the primary spaces start from
        // their own start-up samples, whose b integrates the same target in their own measure.
        lt::PathSpaceSeeds seeds;
        double seedB = -1;
        if (!seedsPath.empty()) {
            auto content = lt::file::readAll(seedsPath, lt::file::FileKind::Paths);
            lt::file::checkSceneHash(content.info, scene->contentHash, content.name, scenePath);
            seeds = lt::seedsFromFile(std::move(content));
            seedB = seeds.b.b();
            if (space != "path" && !quiet)
                std::cerr << "lt-mutate: --space " << space << " starts its chains from its own start-up samples; the "
                          << seeds.paths.size() << " seed paths are for --space path (their b = " << seedB << ")\n";
        }

        const bool pathSpace = space == "path";
        lt::PrimarySpaceSettings ps;
        ps.space = space == "primary" ? lt::PrimarySpace::Kelemen : lt::PrimarySpace::Multiplexed;
        ps.paths.maxDepth = maxDepth != -2 ? maxDepth : scene->integrator.maxDepth;
        ps.paths.rrDepth = scene->integrator.rrDepth;
        if (ps.paths.maxDepth == 0 || ps.paths.maxDepth < -1)
            throw lt::Error("--max-depth must be -1 (unbounded) or at least 1");
        ps.unboundedEdges = unbounded;
        ps.largeStepProbability = largeStep;
        ps.startupSamples = startupSamples;
        ps.startupError = startupError;
        if (!quiet && !pathSpace && ps.space == lt::PrimarySpace::Multiplexed && ps.paths.maxDepth < 0)
            std::cerr << "lt-mutate: warning: the max depth is unbounded; multiplexed chains cover paths of up to "
                      << unbounded << " edges (--max-length-unbounded)\n";

        lt::SampleFilm film(scene->camera);
        const double pixels = double(film.width()) * double(film.height());
        lt::ChainRunSettings rs;
        rs.mutations = mutations > 0 ? mutations : uint64_t(std::llround(mutationsPerPixel * pixels));
        rs.timeLimit = timeLimit;
        rs.chains = chains;
        rs.threads = threads;
        rs.seed = seed;
        rs.mutationsPerRound = round;
        if (!snapshotTimes.empty()) rs.snapshots = lt::SnapshotSchedule::parseTimes(snapshotTimes);
        if (!snapshotMutations.empty()) rs.snapshots = lt::SnapshotSchedule::parseSamples(snapshotMutations);

        nlohmann::json params = {{"space", space},
                                 {"mutations", rs.mutations},
                                 {"time_limit", timeLimit},
                                 {"chains", chains},
                                 {"seed", seed},
                                 {"max_depth", ps.paths.maxDepth},
                                 {"rr_depth", ps.paths.rrDepth},
                                 {"large_step", largeStep},
                                 {"small_step", {{"s1", ps.smallStep.s1()}, {"s2", ps.smallStep.s2()}}},
                                 {"startup_samples", startupSamples},
                                 {"startup_error", startupError},
                                 {"round", round},
                                 {"snapshots", snapshotTimes.empty() ? snapshotMutations : snapshotTimes},
                                 {"resolution", {scene->camera.film().width, scene->camera.film().height}},
                                 {"filter", scene->camera.film().filter.name()},
                                 {"estimator", "expected-value splatting; image = b / N sum f / f* at each state"},
                                 {"target", target}};
        if (target == "gradient") {
            params["gradient_alpha"] = gradientAlpha;
            params["shift_threshold"] = shiftThreshold;
        }
        const lt::PathTarget pathTarget =
            target == "gradient" ? lt::gradientTarget(*scene, gradientAlpha, shiftThreshold) : lt::PathTarget{};
        // Path space: the strategies, and the longest path the bidirectional mutation may build.
        const int maxEdges = ps.paths.maxDepth > 0 ? ps.paths.maxDepth : unbounded;
        lt::MutationChoice choice;
        lt::SceneFeatures features;
        bool usesManifold = false;
        std::optional<lt::NormalChange> preRun; // the manifold perturbation's pre-run, when it had one
        if (pathSpace) {
            params.erase("large_step");
            params.erase("small_step");
            params.erase("startup_error");
            params["refine_b"] = refineB;
            if (!seeds.paths.empty()) params.erase("startup_samples");
            features = lt::analyzeScene(*scene);
            choice = lt::chooseMutations(strategies, features);
            nlohmann::json list = nlohmann::json::array();
            for (const auto& e : choice.chosen)
                list.push_back({{"name", e.name}, {"weight", e.weight}});
            params["strategies"] = list;
            params["max_length"] = maxEdges;
            usesManifold = std::any_of(choice.chosen.begin(), choice.chosen.end(),
                                       [](const auto& e) { return e.name == "manifold"; });
            if (usesManifold) params["lambda"] = lambda;
            if (std::any_of(choice.chosen.begin(), choice.chosen.end(),
                            [](const auto& e) { return e.name == "hslt"; })) {
                params["hslt_gamma"] = hsltGamma;
                params["hslt_stratify"] = hsltStratify;
                params["hslt_jumps"] = hsltJumps == "on";
            }
            if (std::any_of(choice.chosen.begin(), choice.chosen.end(),
                            [](const auto& e) { return e.name == "portal"; })) {
                params["portal_range"] = portalRange;
                if (!features.hasPortals && !quiet)
                    std::cerr << "lt-mutate: warning: portal perturbation: " << features.portalReason
                              << " (it will propose nothing)\n";
            }
            for (const auto& why : choice.leftOut)
                if (!quiet) std::cerr << "lt-mutate: left out: " << why << '\n';
            if (!quiet && ps.paths.maxDepth < 0)
                std::cerr << "lt-mutate: warning: the max depth is unbounded; the bidirectional mutation builds paths "
                             "of up to "
                          << unbounded << " edges (--max-length-unbounded)\n";
        } else if (ps.space == lt::PrimarySpace::Multiplexed) {
            params["max_length"] = maxEdges;
        }
        lt::file::Writer writer(out, lt::file::FileKind::Buffer,
                                lt::tool::makeInfo("lt-mutate", argc, argv, params, scene.get()));
        // Both outputs are opened before any work, so a bad path fails now, not after the seeding.
        std::optional<lt::file::Writer> dumpWriter;
        lt::PathDump dump;
        if (!dumpPaths.empty()) {
            nlohmann::json dparams = params;
            dparams["dump_every"] = dumpEvery;
            dumpWriter.emplace(dumpPaths, lt::file::FileKind::Paths,
                               lt::tool::makeInfo("lt-mutate", argc, argv, dparams, scene.get()));
            dump.every = dumpEvery;
            dump.write = [&](std::vector<lt::file::PathRecord>& records) { dumpWriter->writePaths(records); };
        }
        std::optional<lt::tool::ChainStreamWriter> streamWriter;
        if (!streamPath.empty()) {
            streamWriter.emplace(streamPath, lt::tool::makeInfo("lt-mutate", argc, argv, params, scene.get()));
            dump.writeRound = [&](const lt::file::ChainRound& figures,
                                  std::vector<lt::file::EncodedChainStates>&& states) {
                streamWriter->writeRound(figures, std::move(states));
            };
        }

        lt::tool::installInterruptHandler();
        lt::tool::Progress progress("lt-mutate", quiet);
        const lt::RunProgressCallback onProgress = lt::tool::runProgress(progress, pixels, "mutations/pixel");
        const lt::RunSnapshotCallback onSnapshot = lt::tool::snapshotWriter(writer);
        lt::ChainRunStats stats;
        rs.start = std::chrono::steady_clock::now(); // seeding counts toward the run's time
        if (pathSpace) {
            if (seeds.paths.empty()) {
                // No seed file: a BDPT start-up of our own, as lt-seed --paths would make it.
                progress.update(-1, "seeding with BDPT");
                seeds = lt::seedWithBdpt(*scene, ps.paths, startupSamples, std::max<size_t>(4 * size_t(chains), 1024),
                                         seed ^ 0x5eedULL, threads, &lt::tool::stopRequested(), pathTarget);
                if (!quiet)
                    std::cerr << "lt-mutate: seeded with BDPT (" << startupSamples << " samples): b = " << seeds.b.b()
                              << '\n';
            }
            lt::MutationSettings settings{maxEdges, lambda};
            settings.hsltGamma = hsltGamma;
            settings.hsltStratify = hsltStratify;
            settings.hsltJumps = hsltJumps == "on";
            settings.portalMin = portalRange[0];
            settings.portalMax = portalRange[1];
            if (usesManifold && features.glossySurfaces) {
                // ME App. A1: Delta-theta, which sets how often a glossy vertex is treated as specular, is
                // measured before the chains start and then held (an adaptive chain would not be Markov).
                progress.update(-1, "manifold pre-run");
                std::vector<lt::MarkovPath> states;
                for (size_t i = 0; i < seeds.paths.size() && states.size() < 4096; ++i) {
                    try {
                        states.push_back(lt::pathFromRecord(*scene, seeds.paths[i], i));
                    } catch (const lt::Error&) { // a seed the scene cannot re-create is left to the run to report
                    }
                }
                const auto change = lt::measureNormalChange(*scene, lambda, states, NormalChangePreRun, seed,
                                                            &lt::tool::stopRequested());
                settings.normalChange = change.radians;
                preRun = change;
                if (!quiet)
                    std::cerr << "lt-mutate: manifold pre-run: " << change.proposed << " proposals, " << change.measured
                              << " reached a path; mean normal change at x_b " << change.radians * 180 / lt::Pi
                              << " degrees (held for the run)\n";
            }
            std::vector<std::unique_ptr<lt::Mutation>> owned;
            std::vector<lt::WeightedMutation> mix;
            lt::makeMutations(choice, *scene, settings, owned, mix);
            stats = lt::runPathSpaceChains(*scene, seeds, mix, rs, ps.paths, refineB, film, onProgress,
                                           &lt::tool::stopRequested(), onSnapshot, dump, pathTarget);
            if (dumpWriter) dumpWriter->finish();
            if (streamWriter)
                streamWriter->finish(
                    lt::file::valueTable("normalization", {{"b", stats.normalization.b()},
                                                           {"b_samples", double(stats.normalization.samples())},
                                                           {"mutations", double(stats.mutations)}}));
        } else {
            stats = lt::runPrimarySpaceChains(*scene, ps, rs, film, onProgress, &lt::tool::stopRequested(), onSnapshot);
        }
        progress.finish();
        if (!quiet && timeLimit > 0 && stats.startupSeconds > timeLimit)
            std::cerr << "lt-mutate: warning: the start-up took " << formatSeconds(stats.startupSeconds)
                      << ", longer than --time; the chains ran one round (lower --startup-samples)\n";

        const lt::NormalizationEstimate& b = stats.normalization;
        writer.writeBuffer(film.toBuffer(stats.b));
        writer.writeStats(lt::file::valueTable("run", {{"mutations", double(stats.mutations)},
                                                       {"mutations_per_pixel", double(stats.mutations) / pixels},
                                                       {"chains", double(chains)},
                                                       {"wall_seconds", stats.wallSeconds},
                                                       {"cpu_seconds", stats.cpuSeconds},
                                                       {"startup_seconds", stats.startupSeconds},
                                                       {"rays", double(stats.rays)},
                                                       {"nonfinite_dropped", double(stats.health.nonFinite)},
                                                       {"interrupted", stats.interrupted ? 1.0 : 0.0},
                                                       {"snapshots", double(stats.snapshots)},
                                                       {"snapshot_seconds", stats.snapshotSeconds}}));
        std::vector<std::pair<std::string, double>> norm = {{"b", b.b()},
                                                            {"b_relative_standard_error", b.relativeStandardError()},
                                                            {"b_samples", double(b.samples())},
                                                            {"startup_samples", double(stats.startupSamples)}};
        if (pathSpace) norm.emplace_back("unusable_seeds", double(stats.unusableSeeds));
        if (!pathSpace) {
            norm.emplace_back("startup_work", stats.startupWork);
            norm.emplace_back("startup_relative_standard_error", stats.startupError);
        }
        if (pathTarget) norm.emplace_back("film_b", stats.b);
        if (seedB >= 0) norm.emplace_back("b_seed_file", seedB);
        writer.writeStats(lt::file::valueTable("normalization", norm));
        writer.writeStats(stats.strategies.table());
        for (const auto& t : stats.strategies.walkTables())
            writer.writeStats(t);
        if (preRun)
            writer.writeStats(
                lt::file::valueTable("manifold_prerun", {{"proposals", double(preRun->proposed)},
                                                         {"reached_a_path", double(preRun->measured)},
                                                         {"normal_change_degrees", preRun->radians * 180 / lt::Pi}}));
        if (!pathSpace && ps.space == lt::PrimarySpace::Multiplexed) {
            lt::file::StatTable lengths{
                "path_lengths", {"b", "b_standard_error", "b_samples", "chains_started", "mutations"}, {}, {}};
            for (size_t k = 1; k < b.strata(); ++k) {
                lengths.rows.push_back(std::to_string(k) + " edges");
                lengths.values.push_back({b.stratumB(k), b.stratumStandardError(k), double(b.stratumSamples(k)),
                                          double(stats.chainsPerLength[k]), double(stats.mutationsPerLength[k])});
            }
            writer.writeStats(lengths);
        }
        writer.finish();

        if (!quiet) {
            // A seed file's b comes without its spread: with --refine-b 0 nothing measures it.
            const double se = b.relativeStandardError();
            std::cerr << "lt-mutate: b = " << b.b();
            if (std::isfinite(se))
                std::cerr << " +- " << std::setprecision(2) << 100 * se << "%";
            else
                std::cerr << " (standard error unknown)";
            std::cerr << " from " << b.samples() << " samples (" << stats.startupSamples
                      << (pathSpace ? " of the seed run" : " of the start-up") << ", "
                      << b.samples() - stats.startupSamples << " during the run)";
            if (!pathSpace)
                std::cerr << "; the start-up ended at b +- " << std::setprecision(2) << 100 * stats.startupError
                          << "% after " << std::lround(100 * stats.startupWork) << "% of its budget";
            std::cerr << std::setprecision(6);
            if (pathSpace)
                std::cerr << "; chains started from " << seeds.paths.size() << " seed paths (" << stats.unusableSeeds
                          << " unusable draws skipped)";
            std::cerr << '\n' << stats.strategies.text();
            if (!pathSpace && ps.space == lt::PrimarySpace::Multiplexed) {
                std::cerr << "path lengths (edges: share of b +- standard error, share of the mutations, chains "
                             "started there):\n";
                // Lengths with under 0.01 % of b and of the mutations are summed in one line.
                double restB = 0, restMutations = 0;
                size_t rest = 0;
                for (size_t k = 1; k < b.strata(); ++k) {
                    const double shareB = b.stratumB(k) / b.b();
                    const double shareM =
                        double(stats.mutationsPerLength[k]) / double(std::max<uint64_t>(1, stats.mutations));
                    if (shareB < 1e-4 && shareM < 1e-4) {
                        restB += shareB;
                        restMutations += shareM;
                        ++rest;
                        continue;
                    }
                    std::cerr << "  " << std::setw(2) << k << ": " << std::setprecision(3) << std::setw(6)
                              << 100 * shareB << "% +- " << std::setw(6) << 100 * b.stratumStandardError(k) / b.b()
                              << "%, " << std::setw(6) << 100 * shareM << "%, " << stats.chainsPerLength[k] << '\n';
                }
                if (rest)
                    std::cerr << "  " << rest << " other lengths, each under 0.01 %: " << std::setprecision(2)
                              << 100 * restB << "% of b, " << 100 * restMutations << "% of the mutations together\n";
            }
            std::cerr << "lt-mutate: " << (stats.interrupted ? "interrupted after " : "") << std::setprecision(4)
                      << double(stats.mutations) / pixels << " mutations/pixel in " << formatSeconds(stats.wallSeconds)
                      << " (" << std::setprecision(3) << double(stats.mutations) / stats.wallSeconds / 1e3
                      << "k mutations/s, " << double(stats.rays) / stats.wallSeconds / 1e6 << "M rays/s) -> "
                      << writer.name();
            if (stats.health.nonFinite) std::cerr << " (" << stats.health.nonFinite << " non-finite samples dropped)";
            std::cerr << '\n';
        }
        return stats.interrupted ? lt::tool::interruptedExitCode() : 0;
    });
}
