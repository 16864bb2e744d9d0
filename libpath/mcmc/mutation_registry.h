// Every path-space mutation lt knows, in one table: its name on the command line, what it moves, how to
// make it for a scene, and the rule `--strategies auto` applies. A new mutation is one row of the table
// (mutation_registry.cpp); mutation selection, lt-mutate's help and its messages read it from here.
#pragma once

#include <memory>
#include <span>
#include <string>

#include "mcmc/mutation.h"
#include "scene/scene_features.h"

namespace lt {

// What the mutations of a run are made with.
struct MutationSettings {
    int maxEdges = -1;  // bound on path edges (the bidirectional mutation and lens subpaths keep to it)
    double lambda = 50; // the manifold perturbation's lobe peak relative to the BSDF's (ME Sec. 5.1)
    double normalChange = Pi / 180; // its Delta-theta (ME App. A1; measureNormalChange), radians
    double hsltGamma = 0.1;         // the half-vector mutation's BSDF step scale (HSLT Sec. 6.1)
    double hsltStratify = 0.02;     // its image-plane step, a fraction of the image (HSLT Sec. 6.2; 0: off)
    bool hsltJumps = false;         // its jumps between subspaces after failed walks (HSLT Sec. 5.2; off:
                                    // pipelines/results/hslt/README.md)
    // The portal perturbation's direction kernel, theta in [min, max] radians (Otsu et al. Sec. 5: 2^-8, 2^-4).
    double portalMin = 1.0 / 256, portalMax = 1.0 / 16;
};

struct MutationKind {
    const char* name;    // --strategies NAME
    const char* noun;    // "mutation" or "perturbation": how messages call it
    const char* summary; // what it moves, for --help
    // Makes the mutation for a scene.
    std::unique_ptr<Mutation> (*make)(const Scene& scene, const MutationSettings& settings);
    // Empty when `auto` uses it on a scene with these features; otherwise why auto leaves it out.
    std::string (*autoLeavesOut)(const SceneFeatures& features);
};

// The table, in the order mixes and messages list them.
[[nodiscard]] std::span<const MutationKind> mutationKinds();
// The row named `name`, or null.
[[nodiscard]] const MutationKind* findMutationKind(const std::string& name);

} // namespace lt
