#include "mcmc/mutation_selection.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "math/error.h"
#include "math/number_text.h"
#include "mcmc/mutation_registry.h"

namespace lt {

namespace {

// The names of the mutations lt has, for messages: "bidirectional, lens, ...".
std::string availableList() {
    std::string list;
    for (const auto& k : mutationKinds())
        list += (list.empty() ? "" : ", ") + std::string(k.name);
    return list;
}

} // namespace

MutationChoice chooseMutations(const std::string& spec, const SceneFeatures& features) {
    MutationChoice choice;
    if (spec == "auto") {
        // Each mutation lt has, unless its rule leaves it out on this scene; mutations left out for the
        // same reason are named together ("caustic, multi-chain perturbations: ...").
        std::vector<std::pair<std::string, std::vector<const MutationKind*>>> groups; // reason, kinds
        for (const auto& k : mutationKinds()) {
            const std::string why = k.autoLeavesOut(features);
            if (why.empty()) {
                choice.chosen.push_back({k.name, 1});
                continue;
            }
            auto g = std::find_if(groups.begin(), groups.end(), [&](const auto& x) { return x.first == why; });
            if (g == groups.end()) g = groups.insert(groups.end(), {why, {}});
            g->second.push_back(&k);
        }
        for (const auto& [why, kinds] : groups) {
            std::string names;
            for (const auto* k : kinds)
                names += (names.empty() ? "" : ", ") + std::string(k->name);
            choice.leftOut.push_back(names + " " + kinds.front()->noun + (kinds.size() > 1 ? "s" : "") + ": " + why);
        }
        return choice;
    }
    std::istringstream in(spec);
    std::string item;
    while (std::getline(in, item, ',')) {
        const auto colon = item.find(':');
        MutationChoice::Entry e{item.substr(0, colon), 1};
        if (colon != std::string::npos) {
            const std::string w = item.substr(colon + 1);
            e.weight = numberFromText(w).value_or(0);
            if (!(e.weight > 0) || !std::isfinite(e.weight))
                throw Error("--strategies: weight of '" + e.name + "' must be a positive number, got '" + w + "'");
        }
        const MutationKind* kind = findMutationKind(e.name);
        if (!kind) throw Error("--strategies: unknown mutation '" + e.name + "' (available: " + availableList() + ")");
        for (const auto& c : choice.chosen)
            if (c.name == e.name) throw Error("--strategies: '" + e.name + "' given twice");
        choice.chosen.push_back(e);
    }
    if (choice.chosen.empty()) throw Error("--strategies: empty list");
    if (std::none_of(choice.chosen.begin(), choice.chosen.end(),
                     [](const auto& c) { return c.name == "bidirectional"; }))
        throw Error(
            "--strategies: the list needs the bidirectional mutation (the perturbations alone are not ergodic)");
    return choice;
}

void makeMutations(const MutationChoice& choice, const Scene& scene, const MutationSettings& settings,
                   std::vector<std::unique_ptr<Mutation>>& owned, std::vector<WeightedMutation>& mix) {
    for (const auto& e : choice.chosen) {
        owned.push_back(findMutationKind(e.name)->make(scene, settings));
        mix.push_back({owned.back().get(), e.weight});
    }
}

std::string mutationsHelp() {
    std::string help = "path-space mutations: auto (every mutation the scene can use; says what it leaves out and "
                       "why) or NAME[:WEIGHT],... (weights default to 1) of:";
    for (const auto& k : mutationKinds())
        help += std::string("\n  ") + k.name + ": " + k.summary;
    return help + "\nPrimary spaces have their own two: large step and small step.";
}

} // namespace lt
