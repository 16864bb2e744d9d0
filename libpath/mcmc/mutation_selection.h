// Which path-space mutations a run uses: `--strategies auto` applies each mutation's rule
// (mcmc/mutation_registry.h) to the scene (scene/scene_features.h) and leaves out what cannot help, saying why (the
// third promise); an explicit list NAME[:WEIGHT],... is taken as given. Every mix includes the bidirectional mutation
// (ergodicity: it is the one mutation that can replace any part of a path; MCMC survey, Sec. 3.3).
#pragma once

#include <nlohmann/json.hpp>

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
        const MutationKind* kind = nullptr;
        std::string name;
        double weight = 1;
    };
    std::vector<Entry> chosen;
    std::vector<std::string> leftOut;  // "NAME: why", for the user
    std::vector<std::string> warnings; // what a chosen mutation warns of on this scene (MutationKind::warning)
};

// Throws lt::Error for an unknown name, a weight that is not a positive number, a mutation given twice, or a
// list without the bidirectional mutation.
[[nodiscard]] MutationChoice chooseMutations(const std::string& spec, const SceneFeatures& features,
                                             MutationKinds kinds = mutationKinds());

// The mutations of a choice, made with `values` (the defaults of their options where a value is missing); `mix`
// points into `owned`.
void makeMutations(const MutationChoice& choice, const MutationContext& context, OptionValues values,
                   std::vector<std::unique_ptr<Mutation>>& owned, std::vector<WeightedMutation>& mix);

// What a run records of its mix: "strategies" (name and weight of each) and the values of the chosen mutations'
// options (their defaults where not given).
[[nodiscard]] nlohmann::json mutationParameters(const MutationChoice& choice, OptionValues values);

// Every option of the mutations of `kinds`, in table order.
[[nodiscard]] std::vector<OptionSpec> mutationOptions(MutationKinds kinds = mutationKinds());

// lt-mutate's --help for --strategies: every mutation of `kinds` with what it moves.
[[nodiscard]] std::string mutationsHelp(MutationKinds kinds = mutationKinds());

} // namespace lt
