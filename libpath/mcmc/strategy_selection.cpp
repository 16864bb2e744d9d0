#include "mcmc/strategy_selection.h"

#include <cmath>
#include <sstream>

#include "math/error.h"
#include "mcmc/mutations/bidirectional_mutation.h"

namespace lt {

namespace {

// Mutations of the papers that lt does not have yet: named so that asking for one is a clear error.
const char* const Planned[] = {"lens", "caustic", "multi-chain", "lens-subpath", "manifold", "half-vector", "portal"};

} // namespace

StrategyChoice chooseStrategies(const std::string& spec, const SceneFeatures& features) {
    StrategyChoice choice;
    if (spec == "auto") {
        choice.chosen.push_back({"bidirectional", 1});
        // Veach's perturbations help only where their path types occur (ALGORITHMS.md 2.2-2.4); none is
        // built yet, so say so with what the scene would have needed.
        choice.leftOut.push_back(
            std::string("lens, caustic, multi-chain perturbations: not built yet") +
            (features.specularChains ? " (the scene has specular chains: " + features.specularReason + ")" : ""));
        return choice;
    }
    std::istringstream in(spec);
    std::string item;
    while (std::getline(in, item, ',')) {
        const auto colon = item.find(':');
        StrategyChoice::Entry e{item.substr(0, colon), 1};
        if (colon != std::string::npos) {
            const std::string w = item.substr(colon + 1);
            char* end = nullptr;
            e.weight = std::strtod(w.c_str(), &end);
            if (w.empty() || *end != '\0' || !(e.weight > 0) || !std::isfinite(e.weight))
                throw Error("--strategies: weight of '" + e.name + "' must be a positive number, got '" + w + "'");
        }
        for (const char* p : Planned)
            if (e.name == p) throw Error("--strategies: '" + e.name + "' is not built yet (available: bidirectional)");
        if (e.name != "bidirectional")
            throw Error("--strategies: unknown strategy '" + e.name + "' (available: bidirectional)");
        for (const auto& c : choice.chosen)
            if (c.name == e.name) throw Error("--strategies: '" + e.name + "' given twice");
        choice.chosen.push_back(e);
    }
    if (choice.chosen.empty()) throw Error("--strategies: empty list");
    return choice;
}

void makeMutations(const StrategyChoice& choice, const Scene& scene, int maxEdges,
                   std::vector<std::unique_ptr<Mutation>>& owned, std::vector<WeightedMutation>& mix) {
    for (const auto& e : choice.chosen) {
        if (e.name == "bidirectional") owned.push_back(std::make_unique<BidirectionalMutation>(scene, maxEdges));
        mix.push_back({owned.back().get(), e.weight});
    }
}

} // namespace lt
