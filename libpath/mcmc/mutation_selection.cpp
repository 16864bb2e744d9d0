#include "mcmc/mutation_selection.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "util/error.h"
#include "util/number_text.h"
#include "mcmc/mutation_registry.h"

namespace lt {

namespace {

// The names of the mutations of `kinds`, for messages: "bidirectional, lens, ...".
std::string availableList(MutationKinds kinds) {
    std::string list;
    for (const MutationKind* k : kinds)
        list += (list.empty() ? "" : ", ") + k->name;
    return list;
}

// What the chosen mutations warn of on this scene.
void addWarnings(MutationChoice& choice, const SceneFeatures& features) {
    for (const auto& e : choice.chosen)
        if (e.kind->warning)
            if (std::string w = e.kind->warning(features); !w.empty()) choice.warnings.push_back(std::move(w));
}

} // namespace

MutationChoice chooseMutations(const std::string& spec, const SceneFeatures& features, MutationKinds kinds) {
    MutationChoice choice;
    if (spec == "auto") {
        // Each mutation lt has, unless its rule leaves it out on this scene; mutations left out for the
        // same reason are named together ("caustic, multi-chain perturbations: ...").
        std::vector<std::pair<std::string, std::vector<const MutationKind*>>> groups; // reason, kinds
        for (const MutationKind* k : kinds) {
            const std::string why = k->autoLeavesOut(features);
            if (why.empty()) {
                choice.chosen.push_back({k, k->name, 1});
                continue;
            }
            auto g = std::find_if(groups.begin(), groups.end(), [&](const auto& x) { return x.first == why; });
            if (g == groups.end()) g = groups.insert(groups.end(), {why, {}});
            g->second.push_back(k);
        }
        for (const auto& [why, left] : groups) {
            std::string names;
            for (const auto* k : left)
                names += (names.empty() ? "" : ", ") + k->name;
            choice.leftOut.push_back(names + " " + left.front()->noun + (left.size() > 1 ? "s" : "") + ": " + why);
        }
        addWarnings(choice, features);
        return choice;
    }
    std::istringstream in(spec);
    std::string item;
    while (std::getline(in, item, ',')) {
        const auto colon = item.find(':');
        MutationChoice::Entry e{nullptr, item.substr(0, colon), 1};
        if (colon != std::string::npos) {
            const std::string w = item.substr(colon + 1);
            e.weight = numberFromText(w).value_or(0);
            if (!(e.weight > 0) || !std::isfinite(e.weight))
                throw Error("--strategies: weight of '" + e.name + "' must be a positive number, got '" + w + "'");
        }
        e.kind = findMutationKind(e.name, kinds);
        if (!e.kind)
            throw Error("--strategies: unknown mutation '" + e.name + "' (available: " + availableList(kinds) + ")");
        for (const auto& c : choice.chosen)
            if (c.name == e.name) throw Error("--strategies: '" + e.name + "' given twice");
        choice.chosen.push_back(e);
    }
    if (choice.chosen.empty()) throw Error("--strategies: empty list");
    if (std::none_of(choice.chosen.begin(), choice.chosen.end(),
                     [](const auto& c) { return c.name == "bidirectional"; }))
        throw Error(
            "--strategies: the list needs the bidirectional mutation (the perturbations alone are not ergodic)");
    addWarnings(choice, features);
    return choice;
}

void makeMutations(const MutationChoice& choice, const MutationContext& context, OptionValues values,
                   std::vector<std::unique_ptr<Mutation>>& owned, std::vector<WeightedMutation>& mix) {
    for (const auto& e : choice.chosen) {
        values.setDefaults(e.kind->options);
        owned.push_back(e.kind->make(context, values));
        mix.push_back({owned.back().get(), e.weight});
    }
}

nlohmann::json mutationParameters(const MutationChoice& choice, OptionValues values) {
    nlohmann::json out = nlohmann::json::object();
    nlohmann::json list = nlohmann::json::array();
    for (const auto& e : choice.chosen) {
        list.push_back({{"name", e.name}, {"weight", e.weight}});
        values.setDefaults(e.kind->options);
        out.update(values.record(e.kind->options));
    }
    out["strategies"] = list;
    return out;
}

std::vector<OptionSpec> mutationOptions(MutationKinds kinds) {
    std::vector<OptionSpec> out;
    for (const MutationKind* k : kinds)
        out.insert(out.end(), k->options.begin(), k->options.end());
    return out;
}

std::string mutationsHelp(MutationKinds kinds) {
    std::string help = "path-space mutations: auto (every mutation the scene can use; says what it leaves out and "
                       "why) or NAME[:WEIGHT],... (weights default to 1) of:";
    for (const MutationKind* k : kinds)
        help += "\n  " + k->name + ": " + k->summary;
    return help + "\nPrimary spaces have their own two: large step and small step.";
}

} // namespace lt
