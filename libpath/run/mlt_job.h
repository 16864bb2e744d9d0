// What lt-mutate does between reading its options and writing its files: a Markov-chain run in one of three state
// spaces (Veach-Guibas path space with the mutations of the registry, mcmc/mutation_registry.h; Kelemen's primary
// sample space; Hachisuka's multiplexed space), with the chains' target (luminance, or gradient-domain MLT's), its
// seeding, the mutations' preparations, and the tables and text that report it.
//
// A job is made, then run: made, it has checked its settings against each other and the scene, chosen its
// mutations, and knows what the output records and what to tell the user before any work; run, it seeds (a path
// space without seed paths draws its own with BDPT), prepares the mutations that need it, and runs the chains.
#pragma once

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

#include "mcmc/mutation_selection.h"
#include "mcmc/path_space_chains.h"
#include "mcmc/primary_space_chains.h"
#include "sampling/direct_split.h"

namespace lt {

enum class ChainSpace { Path, Primary, Multiplexed };
enum class ChainTarget { Luminance, Gradient };

// The space named "path", "primary" or "multiplexed" (lt-mutate --space); throws lt::Error for another name.
[[nodiscard]] ChainSpace chainSpace(const std::string& name);

struct MltSettings {
    ChainSpace space = ChainSpace::Path;
    ChainRunSettings run;    // mutations (all chains'), time limit, chains, seed, round, snapshots
    PathSettings paths;      // the path-length bound and Russian roulette of BDPT and the primary spaces
    DirectSplit direct;      // paths of one and two edges rendered apart from the chains (sampling/direct_split.h)
    int unboundedEdges = 12; // the path-length bound of the mutations and multiplexed MLT when paths.maxDepth is -1
    // The primary spaces.
    double largeStep = 0.3;      // probability of a large step (Mitsuba's default)
    uint64_t startupSamples = 0; // the start-up's budget; 0: the space's default (multiplexed 20000, others 100000)
    double startupError = 0.005; // the start-up ends once b's relative standard error is at most this
    // The path space.
    double refineB = 1.0 / 16; // independent BDPT samples per mutation that refine b during the run
    std::string strategies = "auto";
    OptionValues mutationValues; // the mutations' own options (mcmc/mutation_registry.h)
    ChainTarget target = ChainTarget::Luminance;
    double gradientAlpha = 0.2, shiftThreshold = 0.001; // the gradient target's (gdmlt/chain_gradient.h)
    uint64_t dumpEvery = 0; // states handed to PathDump::write: every dumpEvery-th of each chain (0: none)
    bool stream = false;    // the chain-state stream handed to PathDump::writeRound
};

struct MltOutcome {
    ChainRunStats stats;
    file::Buffer image;
    // "run", "normalization", "strategies", the mutations' own figures, their preparations' and (multiplexed)
    // "path_lengths" (formats/SPEC.md).
    std::vector<file::StatTable> tables;
    file::StatTable streamEnd;      // the table a chain-state stream ends with (b, its samples, the mutations)
    std::vector<std::string> notes; // warnings about the run, for the user
    // The direct part's and b's lines, the strategies' table and the path lengths: lines for the user, each ending in
    // '\n'.
    std::string summary;
    std::string rates;   // "8 mutations/pixel in 2.1 s (...k mutations/s, ...M rays/s)": the last line
};

class MltJob {
public:
    // `seeds`: the paths and b of a seed file (sampling/seed_file.h), if one was given. Throws lt::Error for settings
    // that do not fit each other or the scene, and for the mutation list.
    MltJob(const Scene& scene, MltSettings settings, std::optional<PathSpaceSeeds> seeds,
           MutationKinds kinds = mutationKinds());

    // What the output records of the run besides the options every render tool shares (formats/SPEC.md INFO).
    [[nodiscard]] nlohmann::json parameters() const;
    // What the user is told before the run: what auto left out and why, warnings about the settings.
    [[nodiscard]] const std::vector<std::string>& notes() const { return notes_; }

    // Runs the job (once). `control.note` hears of the seeding and the preparations as they end; `dump` receives the
    // dumped states and the chain-state stream.
    [[nodiscard]] MltOutcome run(const RunControl& control, const PathDump& dump = {});

private:
    [[nodiscard]] bool pathSpace() const { return settings_.space == ChainSpace::Path; }
    // Whether the chains have seed paths to start from (a seed file with none leaves the path space to seed itself).
    [[nodiscard]] bool seeded() const { return seeds_ && !seeds_->paths.empty(); }
    [[nodiscard]] int maxEdges() const;
    [[nodiscard]] bool split() const { return settings_.direct.appliesTo(settings_.paths); }
    // Seeds (unless a seed file did), prepares the mutations (their tables into `prepared`) and runs the chains.
    void runPathSpace(const RunControl& control, const PathDump& dump, SampleFilm& film, MltOutcome& out,
                      std::vector<file::StatTable>& prepared);
    [[nodiscard]] std::string summary(const MltOutcome& out, const std::optional<DirectSplitRecord>& direct,
                                      const RenderStats& directStats) const;
    // Warnings when b's relative standard error, or (MMLT) a length's b_k's, is too large for the image to be
    // trusted, naming what to do.
    [[nodiscard]] std::vector<std::string> untrustedB(const ChainRunStats& st) const;
    [[nodiscard]] static std::string rates(const ChainRunStats& st, double pixels);

    const Scene& scene_;
    MltSettings settings_;
    PathSettings chainPaths_; // the chains' paths: settings_.paths without the direct part's when split
    std::optional<PathSpaceSeeds> seeds_;
    std::optional<double> seedFileB_; // a seed file's b, recorded
    MutationKinds kinds_;
    SceneFeatures features_;
    MutationChoice choice_;
    std::vector<std::string> notes_;
};

} // namespace lt
