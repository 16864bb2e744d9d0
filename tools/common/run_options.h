// The options every render tool shares (lt-seed, lt-gradient, lt-mutate), declared, checked and recorded here once:
// the scene and its parameters, the output, the run's length, seed, threads, path depth and snapshots, and how a
// run's progress, snapshots and notes reach the terminal and the output file.
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "common/interrupt.h"
#include "common/progress.h"
#include "common/run_output.h"
#include "common/scene_options.h"
#include "common/tool.h"
#include "image/snapshot_schedule.h"
#include "sampling/parallel_run.h"
#include "sampling/path_settings.h"

namespace lt::tool {

// What differs between the tools in the shared options' words.
struct RunOptionText {
    std::string time;      // --time's help
    std::string snapshots; // what --snapshots adds to its help: when they are taken, what they hold
    std::string countFlag; // the snapshots at counts: "--snapshot-samples" or "--snapshot-mutations"
    std::string countHelp; // its help
};

struct RunOptions {
    std::string scenePath, out, resolution, snapshotTimes, snapshotCounts;
    std::vector<std::string> defines;
    int maxDepth = -2, threads = 0;
    double timeLimit = 0;
    uint64_t seed = 0;
    bool strict = false, quiet = false;
    // When the tool started: a stage of a pipe (lt-gradient --from-paths) counts its time from here, since the
    // stages of a pipe start together.
    RunStart start = RunStart::now();
    std::string tool;

    void add(CLI::App& app, const RunOptionText& text) {
        tool = app.get_name();
        app.add_option("SCENE", scenePath, "Mitsuba 0.5/0.6 scene (.xml)")->required();
        app.add_option("-o,--output", out, "output sample buffer (.lts), or - for stdout")->required();
        app.add_option("--time", timeLimit, text.time)->check(PositiveNumber);
        app.add_option("--max-depth", maxDepth,
                       "longest path in edges, Mitsuba's meaning: 1 = emitters seen directly, -1 = unbounded (default: "
                       "the scene's integrator maxDepth)");
        app.add_option("--threads", threads, "worker threads (default: all cores)")->check(ThreadCount);
        app.add_option("--seed", seed, "random seed (default 0)");
        app.add_option("--resolution", resolution, "film size WxH, overriding the scene's (keeps the horizontal fov)");
        app.add_option("--snapshots", snapshotTimes,
                       "write progress snapshots (SNAP chunks, for lt-error): 'doubling' (1, 2, 4 ... s), "
                       "'doubling:START', or a list of seconds '5,10,30'; " +
                           text.snapshots);
        app.add_option(text.countFlag, snapshotCounts, text.countHelp);
        countFlag_ = text.countFlag;
        app.add_option("-D,--define", defines, "scene parameter NAME=VALUE, overriding the scene's <default>")
            ->type_name("NAME=VALUE");
        addStrictFlag(app, strict);
        app.add_flag("-q,--quiet", quiet, "no progress output");
    }

    // The scene with -D, --resolution and --strict applied, its warnings printed.
    [[nodiscard]] std::unique_ptr<Scene> loadScene() const {
        return loadSceneWithOptions(tool, scenePath, defines, resolution, strict, quiet);
    }

    // The path settings: --max-depth (default: the scene's), Russian roulette from `rrDepth` (0: the scene's).
    [[nodiscard]] PathSettings paths(const Scene& scene, int rrDepth = 0) const {
        PathSettings p;
        p.maxDepth = maxDepth != -2 ? maxDepth : scene.integrator.maxDepth;
        p.rrDepth = rrDepth > 0 ? rrDepth : scene.integrator.rrDepth;
        if (p.maxDepth == 0 || p.maxDepth < -1) throw Error("--max-depth must be -1 (unbounded) or at least 1");
        return p;
    }

    // The pixels of the scene's film that an image has (its crop window): what "per pixel" counts.
    [[nodiscard]] static double pixels(const Scene& scene) {
        return double(scene.camera.film().cropWidth) * double(scene.camera.film().cropHeight);
    }

    // The snapshot schedule; throws for both kinds given or one that does not parse (call it before any work).
    [[nodiscard]] SnapshotSchedule snapshots() const {
        if (!snapshotTimes.empty() && !snapshotCounts.empty())
            throw Error("give --snapshots or " + countFlag_ + ", not both");
        if (!snapshotTimes.empty()) return SnapshotSchedule::parseTimes(snapshotTimes);
        if (!snapshotCounts.empty()) return SnapshotSchedule::parseSamples(snapshotCounts);
        return {};
    }

    // What an output records of these options (formats/SPEC.md INFO parameters).
    [[nodiscard]] nlohmann::json parameters(const Scene& scene, const PathSettings& paths) const {
        return {{"seed", seed},
                {"time_limit", timeLimit},
                {"snapshots", snapshotTimes.empty() ? snapshotCounts : snapshotTimes},
                {"max_depth", paths.maxDepth},
                {"rr_depth", paths.rrDepth},
                {"resolution", {scene.camera.film().width, scene.camera.film().height}},
                {"filter", scene.camera.film().filter.name()}};
    }

    // How a run reports to this tool: progress on `progress` in `unit` per pixel of `pixels`, snapshots into
    // `writer`, notes on stderr, Ctrl-C. The run's clock starts with the run unless the caller sets `start`.
    [[nodiscard]] RunControl control(Progress& progress, file::Writer& writer, double pixels,
                                     const std::string& unit) const {
        installInterruptHandler();
        RunControl c(threads, snapshotWriter(writer));
        c.stop = &stopRequested();
        c.progress = runProgress(progress, pixels, unit);
        if (!quiet) c.note = [name = tool](const std::string& line) { std::cerr << name << ": " << line << '\n'; };
        return c;
    }

    // The end of an output: its final buffer, its tables, END!.
    static void finish(file::Writer& writer, const file::Buffer& image, const std::vector<file::StatTable>& tables) {
        writer.writeBuffer(image);
        for (const auto& t : tables)
            writer.writeStats(t);
        writer.finish();
    }

    // A line for the user unless quiet.
    void tell(const std::string& line) const {
        if (!quiet) std::cerr << tool << ": " << line << '\n';
    }

private:
    std::string countFlag_;
};

} // namespace lt::tool
