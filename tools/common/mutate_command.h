// lt-mutate's routine: its options (the shared ones of run_options.h, the chains', and every mutation's own from the
// registry it is given, mcmc/mutation_registry.h), the checks of what the user gave, the outputs opened before any
// work, the run (run/mlt_job.h) and the files and lines it ends with. The registry is a parameter so that a test can
// run the tool with a mutation of its own.
#pragma once

#include <CLI/CLI.hpp>

#include <chrono>
#include <optional>
#include <string>

#include "common/chain_stream_writer.h"
#include "common/info.h"
#include "common/registry_options.h"
#include "common/run_options.h"
#include "run/mlt_job.h"

namespace lt::tool {

class MutateCommand {
public:
    MutateCommand(CLI::App& app, MutationKinds kinds) : app_(app), kinds_(kinds) {
        run_.add(app, {"run for this many seconds, start-up included", "taken at the end of a round of the chains",
                       "--snapshot-mutations", "write snapshots at these mutations per pixel, e.g. '1,4,16'"});
        app.add_option("SEEDS", seedsPath_,
                       "seed paths from lt-seed --paths (.ltp, or - for stdin) for --space path; without it the tool "
                       "seeds itself with BDPT");
        addChainOptions();
        app.add_option("--strategies", s_.strategies, mutationsHelp(kinds));
        mutationOptions_.add(app, mutationOptions(kinds));
        addOutputOptions();
    }

    // The tool's body: exit code 0, or 128 + the signal that stopped it early.
    int run(int argc, char** argv) {
        checkOptions();
        s_.mutationValues = mutationOptions_.given(app_);
        s_.run.snapshots = run_.snapshots();
        requireChainMemory(s_.run.chains); // before the scene and the start-up, which keeps 4 seeds per chain
        auto scene = run_.loadScene();
        const MltSettings settings = mltSettings(*scene);
        std::optional<PathSpaceSeeds> seeds;
        if (!seedsPath_.empty()) {
            auto content = file::readAll(seedsPath_, file::FileKind::Paths);
            file::checkSceneHash(content.info, scene->contentHash, content.name, run_.scenePath);
            seeds = seedsFromFile(std::move(content), settings.direct.chainPaths(settings.paths).minDepth);
        }
        MltJob job(*scene, settings, std::move(seeds), kinds_);
        for (const auto& note : job.notes())
            run_.tell(note);

        // Every output is opened before any work, so a bad path fails now, not after the seeding.
        nlohmann::json params = run_.parameters(*scene, settings.paths);
        params.update(job.parameters());
        file::Writer writer(run_.out, file::FileKind::Buffer, makeInfo("lt-mutate", argc, argv, params, scene.get()));
        std::optional<file::Writer> dumpWriter;
        std::optional<ChainStreamWriter> streamWriter;
        const PathDump dump = openDumps(params, scene.get(), argc, argv, dumpWriter, streamWriter);

        Progress progress("lt-mutate", run_.quiet);
        RunControl control = run_.control(progress, writer, RunOptions::pixels(*scene), "mutations/pixel");
        control.start = RunStart::now(); // the seeding and the direct part count toward the run's time
        const MltOutcome out = job.run(control, dump);
        progress.finish();
        if (dumpWriter) dumpWriter->finish();
        if (streamWriter) streamWriter->finish(out.streamEnd);
        for (const auto& note : out.notes)
            run_.tell(note);
        RunOptions::finish(writer, out.image, out.tables);
        if (!run_.quiet)
            std::cerr << "lt-mutate: " << out.summary << "lt-mutate: " << out.rates << " -> " << writer.name() << '\n';
        return out.stats.interrupted ? interruptedExitCode() : 0;
    }

private:
    void addChainOptions() {
        app_.add_option("--space", space_,
                        "path (default; Veach-Guibas MLT), primary (Kelemen PSSMLT) or multiplexed (Hachisuka MMLT)")
            ->check(CLI::IsMember({"primary", "multiplexed", "path"}));
        app_.add_option("--mutations", mutations_, "total mutations over all chains")->check(PositiveNumber);
        app_.add_option("--mutations-per-pixel", mutationsPerPixel_, "total mutations as a multiple of the pixel count")
            ->check(PositiveNumber);
        app_.add_option("--chains", s_.run.chains, "independent chains (default 256, whatever the thread count)")
            ->check(PositiveNumber);
        app_.add_option("--max-length-unbounded", s_.unboundedEdges,
                        "multiplexed, max depth -1: the path lengths the start-up covers first (default 12); it "
                        "doubles them while the paths beyond carry over 0.1 % of b, up to 1023 edges (the path-space "
                        "mutations and PSSMLT need no bound)")
            ->check(PositiveNumber);
        app_.add_option("--large-step", s_.largeStep, "probability of a large step (default 0.3, Mitsuba's)")
            ->check(CLI::Range(0.0, 1.0));
        app_.add_option("--startup-samples", s_.startupSamples,
                        "independent samples that first estimate b and seed the chains, at most (default 100000; "
                        "multiplexed: per path length on average, default 20000, the same work for each length; path "
                        "space without a seed file: BDPT samples, all of them). The primary spaces spend 1/8 of it "
                        "evenly, then rounds with a quarter evenly and the rest where b's spread is (Neyman allocation "
                        "over the lengths), and stop once b is known to --startup-error")
            ->check(PositiveNumber);
        app_.add_option("--startup-error", s_.startupError,
                        "primary spaces: the start-up stops once b's relative standard error is at most this (default "
                        "0.005; 0 spends all of --startup-samples). The large steps refine b during the run")
            ->check(CLI::Range(0.0, 1.0));
        app_.add_option("--refine-b", s_.refineB,
                        "path space: independent BDPT samples per mutation that keep refining b during the run "
                        "(default 0.0625, one per 16 mutations of a chain; 0 keeps the seed run's b). The primary "
                        "spaces refine b with their large steps")
            ->check(CLI::Range(0.0, 1.0));
        app_.add_option("--direct-samples", s_.direct.samples,
                        "samples per pixel of the direct part: paths of 1 and 2 edges (emitters seen directly, direct "
                        "illumination) rendered by path tracing with MIS and Sobol samples, the chains (their start-up, "
                        "seeds and b) render the rest; the image is the sum, and its direct.R/G/B channels and STAT "
                        "direct_split say how much came from each (default 16, as Mitsuba's directSamples; -1: the "
                        "chains render every path). Seed files must be made for the same split (lt-seed "
                        "--direct-split)");
        app_.add_option("--round", s_.run.mutationsPerRound,
                        "mutations per chain between merges (default 64; sets the granularity of snapshots, not the "
                        "estimate)")
            ->check(PositiveNumber);
        app_.add_option(
                "--target", target_,
                "path space: the function the chains sample: luminance (default; MLT) or gradient (gradient-domain "
                "MLT, "
                "Lehtinen et al. 2013: the luminance of the differences to the four neighbouring pixels' shifted paths "
                "plus --gradient-alpha times the path's own; for --stream and lt-gradient --from-paths). b stays the "
                "integral of luminance; the image is read with b N / (sum of the credits x lum f / f*)")
            ->check(CLI::IsMember({"luminance", "gradient"}));
        app_.add_option("--gradient-alpha", s_.gradientAlpha,
                        "--target gradient: weight of the path's own luminance in the target (default 0.2)")
            ->check(PositiveNumber);
        app_.add_option("--shift-threshold", s_.shiftThreshold,
                        "--target gradient: Beckmann roughness at or below which the shift follows a vertex's half "
                        "vector instead of reconnecting (default 0.001, as lt-gradient)")
            ->check(NonNegativeNumber);
    }

    void addOutputOptions() {
        app_.add_option("--dump-paths", dumpPaths_,
                        "path space: write every K-th state of every chain to a paths file (.ltp, or - for stdout) for "
                        "trace plots and lt-inspect; rngStream = chain, rngOffset = mutation");
        app_.add_option("--dump-every", dumpEvery_, "with --dump-paths: K (mutations of a chain between dumped states)")
            ->check(PositiveNumber);
        app_.add_option("--stream", streamPath_,
                        "path space: write the chain-state stream to a paths file (.ltp, or - for stdout): every state "
                        "the image credited, with its credit, f, f* and each round's mutation count and b, for "
                        "lt-gradient --from-paths (CHST chunks, formats/SPEC.md)");
    }

    // What the user gave that does not go together.
    void checkOptions() const {
        s_.direct.check();
        const bool path = space_ == "path";
        if (!path) {
            if (!dumpPaths_.empty()) throw Error("--dump-paths needs --space path");
            if (!streamPath_.empty()) throw Error("--stream needs --space path");
            if (target_ != "luminance") throw Error("--target " + target_ + " needs --space path");
            if (app_.count("--strategies") && s_.strategies != "auto")
                throw Error("--strategies selects path-space mutations; --space " + space_ +
                            " has its own (large and small steps, --large-step)");
            for (const OptionSpec& spec : mutationOptions(kinds_))
                if (app_.count(spec.flag)) throw Error(spec.flag + " is for --space path");
            if (app_.count("--refine-b"))
                throw Error("--refine-b is for --space path; the primary spaces refine b with their large steps");
        } else if (app_.count("--large-step")) {
            throw Error("--large-step is for --space primary and multiplexed");
        }
        if (space_ != "multiplexed" && app_.count("--max-length-unbounded"))
            throw Error("--max-length-unbounded is for --space multiplexed (the path-space mutations and PSSMLT build "
                        "paths of any length with --max-depth -1)");
        if (dumpPaths_.empty() != (dumpEvery_ == 0)) throw Error("--dump-paths and --dump-every go together");
        if (target_ != "gradient" && (app_.count("--gradient-alpha") || app_.count("--shift-threshold")))
            throw Error("--gradient-alpha and --shift-threshold are options of --target gradient");
        if (int(run_.out == "-") + int(dumpPaths_ == "-") + int(streamPath_ == "-") > 1)
            throw Error("only one of -o, --dump-paths and --stream can be stdout");
        if (!streamPath_.empty() && (streamPath_ == run_.out || streamPath_ == dumpPaths_))
            throw Error("--stream needs a file of its own");
        const int bounds = (mutations_ > 0) + (mutationsPerPixel_ > 0);
        if (bounds > 1) throw Error("give --mutations or --mutations-per-pixel, not both");
        if (bounds == 0 && !(run_.timeLimit > 0)) throw Error("give --mutations, --mutations-per-pixel or --time");
    }

    // The settings the options bound (s_), completed with what the scene and the other options decide.
    [[nodiscard]] MltSettings mltSettings(const Scene& scene) const {
        MltSettings s = s_;
        s.space = chainSpace(space_);
        s.paths = run_.paths(scene);
        s.run.mutations =
            mutations_ > 0 ? mutations_ : uint64_t(std::llround(mutationsPerPixel_ * RunOptions::pixels(scene)));
        s.run.timeLimit = run_.timeLimit;
        s.run.seed = run_.seed;
        s.target = target_ == "gradient" ? ChainTarget::Gradient : ChainTarget::Luminance;
        s.dumpEvery = dumpEvery_;
        s.stream = !streamPath_.empty();
        return s;
    }

    // The writers of --dump-paths and --stream, opened, and what the chains hand them.
    PathDump openDumps(const nlohmann::json& params, const Scene* scene, int argc, char** argv,
                       std::optional<file::Writer>& dumpWriter, std::optional<ChainStreamWriter>& streamWriter) const {
        PathDump dump;
        if (!dumpPaths_.empty()) {
            nlohmann::json p = params;
            p["dump_every"] = dumpEvery_;
            dumpWriter.emplace(dumpPaths_, file::FileKind::Paths, makeInfo("lt-mutate", argc, argv, p, scene));
            dump.every = dumpEvery_;
            dump.write = [&dumpWriter](std::vector<file::PathRecord>& records) { dumpWriter->writePaths(records); };
        }
        if (!streamPath_.empty()) {
            streamWriter.emplace(streamPath_, makeInfo("lt-mutate", argc, argv, params, scene));
            dump.writeRound = [&streamWriter](const file::ChainRound& figures,
                                              std::vector<file::EncodedChainStates>&& states) {
                streamWriter->writeRound(figures, std::move(states));
            };
        }
        return dump;
    }

    CLI::App& app_;
    MutationKinds kinds_;
    RunOptions run_;
    RegistryOptions mutationOptions_;
    MltSettings s_; // the options bound to the settings they set, with the settings' defaults
    std::string seedsPath_, space_ = "path", target_ = "luminance", dumpPaths_, streamPath_;
    uint64_t mutations_ = 0, dumpEvery_ = 0;
    double mutationsPerPixel_ = 0;
};

} // namespace lt::tool
