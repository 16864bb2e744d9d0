// lt-gradient --from-paths: the gradient stage of gradient-domain MLT (run/stream_gradient_job.h) on lt-mutate's
// chain-state stream, with the shared options of the render command it stands beside (render_command.h), of which
// those that shape path tracing do not apply.
#pragma once

#include <CLI/CLI.hpp>

#include <set>
#include <string>

#include "common/info.h"
#include "common/run_options.h"
#include "run/stream_gradient_job.h"

namespace lt::tool {

class StreamGradientCommand {
public:
    explicit StreamGradientCommand(CLI::App& app) : app_(app) {
        app.add_option("--from-paths", stream_,
                       "the chain-state stream of lt-mutate --stream (a file, or - for stdin): estimate primal, dx, dy "
                       "and direct from the chains' states (gradient-domain MLT) instead of tracing base paths; the "
                       "options of the path tracers (--method, --spp, --time, --tile, --max-depth, --rr-*, --seed) do "
                       "not apply");
    }

    [[nodiscard]] bool given() const { return !stream_.empty(); }

    // `values`: the estimators' options given (of which --shift-threshold applies).
    int run(const RunOptions& run, OptionValues values, int argc, char** argv) {
        // What applies to the gradient stage; every other option shapes the path tracers' own sampling.
        static const std::set<std::string> applies = {
            "SCENE",     "--output", "--from-paths", "--resolution", "--snapshots", "--shift-threshold",
            "--threads", "--define", "--strict",     "--quiet",      "--help"};
        for (const CLI::Option* o : app_.get_options())
            if (o->count() > 0 && !applies.count(o->get_name()))
                throw Error(o->get_name() + " is not an option of --from-paths");
        ChainStreamSettings settings;
        values.setDefaults({shiftThresholdOption()});
        settings.shiftThreshold = values.number("shift_threshold");
        settings.snapshots = run.snapshots();
        auto scene = run.loadScene();
        file::Reader stream(stream_, file::FileKind::Paths);
        StreamGradientJob job(*scene, stream, settings);
        nlohmann::json params = job.parameters();
        params["stream"] = stream_;
        params["snapshots"] = run.snapshotTimes;
        params["resolution"] = {scene->camera.film().width, scene->camera.film().height};
        params["filter"] = scene->camera.film().filter.name();
        file::Writer writer(run.out, file::FileKind::Buffer,
                            makeInfo(app_.get_name(), argc, argv, params, scene.get()));
        Progress progress(app_.get_name(), run.quiet);
        RunControl control = run.control(progress, writer, RunOptions::pixels(*scene), "mutations/pixel");
        control.start = run.start; // a pipe's stages start together (gdmlt/chain_stream.h: times)
        const StreamGradientOutcome out = job.run(control);
        progress.finish();
        RunOptions::finish(writer, out.image, out.tables);
        run.tell(out.summary + " -> " + writer.name());
        return out.stats.interrupted ? interruptedExitCode() : 0;
    }

private:
    CLI::App& app_;
    std::string stream_;
};

} // namespace lt::tool
