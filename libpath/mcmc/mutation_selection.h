// Which path-space mutations a run uses: `--strategies auto` applies each mutation's rule
// (mcmc/mutation_registry.h) to the scene (scene/scene_features.h) and leaves out what cannot help, saying why (the
// third promise); an explicit list NAME[:WEIGHT],... is taken as given. Every mix includes the bidirectional mutation
// (ergodicity: it is the one mutation that can replace any part of a path; MCMC survey, Sec. 3.3).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "mcmc/mutation.h"
#include "mcmc/mutation_registry.h"
#include "mcmc/path_space_chains.h"
#include "scene/scene_features.h"

namespace lt {

struct MutationChoice {
    struct Entry {
        std::string name;
        double weight = 1;
    };
    std::vector<Entry> chosen;
    std::vector<std::string> leftOut; // "NAME: why", for the user
};

// Throws lt::Error for an unknown name, a weight that is not a positive number, a mutation that is not
// built yet, or a list without the bidirectional mutation.
[[nodiscard]] MutationChoice chooseMutations(const std::string& spec, const SceneFeatures& features);

// The mutations of a choice, for a scene; `mix` points into `owned`.
void makeMutations(const MutationChoice& choice, const Scene& scene, const MutationSettings& settings,
                   std::vector<std::unique_ptr<Mutation>>& owned, std::vector<WeightedMutation>& mix);

// lt-mutate's --help for --strategies: every mutation of the registry (mcmc/mutation_registry.h) with
// what it moves.
[[nodiscard]] std::string mutationsHelp();

} // namespace lt
