// Every path-space mutation lt knows, in one table: a row per mutation, which the mutation's own file defines
// (its name on the command line, what it moves, its options, how to make it for a scene, the rule `--strategies
// auto` applies, and any work it needs before the chains start). A new mutation is its own files and one line of
// the table (mutation_registry.cpp); mutation selection, lt-mutate's options, help and messages, and the
// parameters an output records all read it from here.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "formats/records.h"
#include "mcmc/mutation.h"
#include "scene/scene_features.h"
#include "util/option_spec.h"

namespace lt {

// What a mutation is made with besides its own options.
struct MutationContext {
    const Scene& scene;
    int maxEdges = -1; // bound on path edges (the bidirectional mutation and lens subpaths keep to it)
    int minEdges = 1;  // the fewest edges the chains' paths have (PathSettings::minDepth; the bidirectional mutation)
};

// What a mutation's preparation sees before the chains start (MutationKind::prepare).
struct PrepareContext {
    const Scene& scene;
    const SceneFeatures& features;
    const std::vector<file::PathRecord>& seeds; // the chains' seed paths
    uint64_t seed = 0;                          // the run's
    const std::atomic<bool>* stop = nullptr;    // Ctrl-C
};

// What a preparation found: a table for the output file and a line for the user.
struct Preparation {
    file::StatTable table;
    std::string message;
};

struct MutationKind {
    std::string name;                // --strategies NAME
    std::string noun;                // "mutation" or "perturbation": how messages call it
    std::string summary;             // what it moves, for --help
    std::vector<OptionSpec> options; // its own options (their values reach make() and the output's parameters)
    // Makes the mutation.
    std::function<std::unique_ptr<Mutation>(const MutationContext&, const OptionValues&)> make;
    // Empty when `auto` uses it on a scene with these features; otherwise why auto leaves it out.
    std::function<std::string(const SceneFeatures&)> autoLeavesOut;
    // Optional work before the chains start, with the seed paths at hand: it may add values make() reads, and
    // returns what to record and tell, or nothing when there was nothing to do.
    std::function<std::optional<Preparation>(const PrepareContext&, OptionValues&)> prepare;
    // Optional: a warning for the user when the mutation is in a run's mix on a scene with these features (empty:
    // none).
    std::function<std::string(const SceneFeatures&)> warning;
};

// The registry: every mutation lt has, in the order mixes and messages list them.
using MutationKinds = std::span<const MutationKind* const>;
[[nodiscard]] MutationKinds mutationKinds();
// The row named `name`, or null.
[[nodiscard]] const MutationKind* findMutationKind(const std::string& name, MutationKinds kinds = mutationKinds());

} // namespace lt
