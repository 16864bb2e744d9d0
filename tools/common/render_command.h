// The one routine of the render tools that run a pixel estimator (lt-seed: BDPT and the path tracer; lt-gradient:
// the gradient-domain estimators): their options (the shared ones of run_options.h, --method and --spp, and each
// estimator's own from the registry, run/estimator_registry.h), their checks, the outputs opened before any work,
// the run (run/render_job.h), and the files and lines it ends with. A tool names its estimators and what else it
// offers (lt-seed: seed paths for the Markov chains, the sampler, the tile size).
#pragma once

#include <CLI/CLI.hpp>

#include <algorithm>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "common/info.h"
#include "common/registry_options.h"
#include "common/run_options.h"
#include "run/estimator_registry.h"
#include "run/render_job.h"
#include "sampling/direct_split.h"
#include "sampling/seed_file.h"

namespace lt::tool {

struct RenderFrontEnd {
    std::vector<std::string> methods; // the estimators it offers, the default first
    std::string timeHelp;             // --time's help
    std::string snapshotsHelp;        // when --snapshots are taken and what they hold
    bool seedPaths = false;           // --paths and --max-paths, --sampler and --tile (lt-seed)
};

class RenderCommand {
public:
    RenderCommand(CLI::App& app, RenderFrontEnd front)
        : app_(app), front_(std::move(front)), kinds_(estimatorKinds(front_.methods)), method_(front_.methods[0]) {
        run_.add(app, {front_.timeHelp, front_.snapshotsHelp, "--snapshot-samples",
                       "write snapshots at these samples per pixel, e.g. '1,4,16'"});
        std::string methods;
        for (const EstimatorKind* k : kinds_)
            methods +=
                (methods.empty() ? "" : "; ") + k->name + (k == kinds_[0] ? " (default)" : "") + ": " + k->summary;
        app.add_option("--method", method_, methods)->check(CLI::IsMember(front_.methods));
        app.add_option(
               "--spp", spp_,
               "samples per pixel (base paths per pixel; default: the scene's sampleCount; with --time, an upper "
               "bound)")
            ->check(PositiveNumber);
        app.add_option("--rr-depth", rrDepth_,
                       "edges after which Russian roulette starts (default: the scene's rrDepth)")
            ->check(PositiveNumber);
        for (const EstimatorKind* k : kinds_)
            estimatorOptions_.add(app, k->options);
        if (front_.seedPaths) addSeedOptions();
    }

    [[nodiscard]] const RunOptions& options() const { return run_; }
    // The estimators' options given on the command line.
    [[nodiscard]] OptionValues estimatorValues() const { return estimatorOptions_.given(app_); }

    // The tool's body: exit code 0, or 128 + the signal that stopped it early.
    int run(int argc, char** argv) {
        const EstimatorKind& kind =
            **std::find_if(kinds_.begin(), kinds_.end(), [&](const EstimatorKind* k) { return k->name == method_; });
        checkOptions(kind);
        const OptionValues values = withDefaults(kind);
        const SnapshotSchedule snapshots = run_.snapshots();
        auto scene = run_.loadScene();
        const PathSettings paths = run_.paths(*scene, rrDepth_);
        RenderSettings rs;
        rs.paths = paths;
        rs.spp = spp_ > 0 ? spp_ : (run_.timeLimit > 0 ? 0 : scene->integrator.sampleCount);
        rs.timeLimit = run_.timeLimit;
        rs.seed = run_.seed;
        rs.sampler = sampler_ == "sobol" ? SamplerKind::Sobol : SamplerKind::Independent;
        rs.tileSize = tile_;
        rs.snapshots = snapshots;
        if (kind.warning)
            if (const std::string w = kind.warning(values); !w.empty())
                std::cerr << app_.get_name() << ": warning: " << w << '\n';

        // The outputs are opened before the work, so a bad path fails now and not after an hour of rendering.
        nlohmann::json params = run_.parameters(*scene, paths);
        params.update(estimatorParameters(kind, values));
        params["method"] = kind.name;
        params["spp"] = rs.spp;
        if (front_.seedPaths) {
            params["sampler"] = sampler_;
            params["tile"] = tile_;
        }
        file::Writer writer(run_.out, file::FileKind::Buffer,
                            makeInfo(app_.get_name(), argc, argv, params, scene.get()));
        std::optional<file::Writer> pathWriter;
        std::optional<SeedReservoir> reservoir;
        if (!pathsOut_.empty()) {
            pathWriter.emplace(pathsOut_, file::FileKind::Paths,
                               makeInfo(app_.get_name(), argc, argv, seedParameters(params), scene.get()));
            reservoir.emplace(maxPaths_, run_.seed ^ 0x9e3779b97f4a7c15ULL, seedSplit().chainPaths(paths).minDepth);
        }

        const auto estimator = kind.make(*scene, paths, values);
        const double pixels = RunOptions::pixels(*scene);
        Progress progress(app_.get_name(), run_.quiet);
        const RenderOutcome out = renderImage(*scene, *estimator, rs, run_.control(progress, writer, pixels, "spp"),
                                              reservoir ? &*reservoir : nullptr);
        progress.finish();
        RunOptions::finish(writer, out.image, out.tables);
        if (pathWriter) {
            const auto written = writeSeedFile(*pathWriter, *reservoir, out.stats.samples, pixels);
            run_.tell("b = " + numberText(written.b) + " (" + std::to_string(reservoir->candidates()) +
                      " candidates, " + std::to_string(written.kept) + " kept) -> " + pathWriter->name());
        }
        run_.tell(kind.name + ", " + out.summary + " -> " + writer.name());
        return out.stats.interrupted ? interruptedExitCode() : 0;
    }

private:
    void addSeedOptions() {
        app_.add_option("--paths", pathsOut_, "also write candidate seed paths (.ltp), or - for stdout");
        app_.add_option("--max-paths", maxPaths_,
                        "seed paths to keep: independent draws in proportion to weight (default 100000)")
            ->check(PositiveNumber);
        app_.add_option("--direct-split", directSplit_,
                        "with --paths: on (default) leaves the paths of 1 and 2 edges out of the seed paths and their b, "
                        "for lt-mutate's chains that leave them to the direct part (its default, --direct-samples); off "
                        "keeps them, for lt-mutate --direct-samples -1. The image is whole either way")
            ->check(CLI::IsMember({"on", "off"}));
        app_.add_option("--sampler", sampler_,
                        "random numbers of a pixel's samples: independent (default; PCG32) or sobol (padded "
                        "Owen-scrambled Sobol' points, Burley 2020: each 1D and 2D sample of a path is stratified over "
                        "the pixel's samples, which lowers the noise of smooth regions, most at 2^k samples per pixel; "
                        "unbiased)")
            ->check(CLI::IsMember({"independent", "sobol"}));
        app_.add_option("--tile", tile_, "tile size in pixels (default 32; changes the sample order, not the estimate)")
            ->check(PositiveNumber);
    }

    void checkOptions(const EstimatorKind& kind) const {
        std::vector<OptionSpec> all;
        for (const EstimatorKind* k : kinds_)
            all.insert(all.end(), k->options.begin(), k->options.end());
        RegistryOptions::refuseOthers(app_, all, kind.options, "--method " + othersThan(kind));
        if (!front_.seedPaths) return;
        if (run_.out == "-" && pathsOut_ == "-") throw Error("only one of -o and --paths can be stdout");
        if (pathsOut_.empty() && app_.count("--max-paths")) throw Error("--max-paths needs --paths");
        if (pathsOut_.empty() && app_.count("--direct-split")) throw Error("--direct-split needs --paths");
        if (kind.name != "bdpt" && !pathsOut_.empty())
            throw Error("--paths needs --method bdpt (seed paths are BDPT strategies)");
    }

    // The estimators other than `kind` whose options those are: "gdpr".
    [[nodiscard]] std::string othersThan(const EstimatorKind& kind) const {
        std::string names;
        for (const EstimatorKind* k : kinds_)
            if (k != &kind) names += (names.empty() ? "" : " or ") + k->name;
        return names;
    }

    [[nodiscard]] OptionValues withDefaults(const EstimatorKind& kind) const {
        OptionValues values = estimatorValues();
        values.setDefaults(kind.options);
        return values;
    }

    // The split of the chains the seed paths are for (sampling/direct_split.h): only whether there is one matters.
    [[nodiscard]] DirectSplit seedSplit() const {
        DirectSplit split;
        if (directSplit_ == "off") split.samples = -1;
        return split;
    }

    [[nodiscard]] nlohmann::json seedParameters(nlohmann::json p) const {
        p["max_paths"] = maxPaths_;
        p["direct_split"] = directSplit_;
        p["selection"] = "independent draws with replacement, each proportional to weight over all candidates (K "
                         "weighted reservoirs of size one): pick uniformly among them";
        p["b_convention"] = "STAT normalization.b = integral over the sensor's raster positions of (crop pixels) x "
                            "luminance(f), the Markov chains' normalization; camera-strategy weights are divided by "
                            "the sum of the pixel filters at their raster position";
        return p;
    }

    [[nodiscard]] static std::string numberText(double v) {
        std::ostringstream o;
        o << v;
        return o.str();
    }

    CLI::App& app_;
    RenderFrontEnd front_;
    std::vector<const EstimatorKind*> kinds_;
    RunOptions run_;
    RegistryOptions estimatorOptions_;
    std::string method_, pathsOut_, sampler_ = "independent", directSplit_ = "on";
    int spp_ = 0, rrDepth_ = 0, tile_ = 32;
    size_t maxPaths_ = 100000;
};

} // namespace lt::tool
