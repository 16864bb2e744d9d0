#include "mcmc/strategy_selection.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "math/error.h"
#include "mcmc/mutations/bidirectional_mutation.h"
#include "mcmc/mutations/caustic_perturbation.h"
#include "mcmc/mutations/lens_perturbation.h"
#include "mcmc/mutations/lens_subpath_mutation.h"
#include "mcmc/mutations/multi_chain_perturbation.h"

namespace lt {

namespace {

// The path-space mutations lt has (default weight 1 each).
const char* const Available[] = {"bidirectional", "lens", "caustic", "multi-chain", "lens-subpath"};
const char* const AvailableList = "bidirectional, lens, caustic, multi-chain, lens-subpath";

// Mutations of the papers that lt does not have yet: named so that asking for one is a clear error.
const char* const Planned[] = {"manifold", "half-vector", "portal"};

} // namespace

StrategyChoice chooseStrategies(const std::string& spec, const SceneFeatures& features) {
    StrategyChoice choice;
    if (spec == "auto") {
        // Veach's mix (ALGORITHMS.md 2): the bidirectional mutation and the lens perturbation always; the
        // caustic and multi-chain perturbations only move paths through specular chains (2.3, 2.4).
        choice.chosen = {{"bidirectional", 1}, {"lens", 1}};
        if (features.specularChains) {
            choice.chosen.push_back({"caustic", 1});
            choice.chosen.push_back({"multi-chain", 1});
        } else {
            choice.leftOut.push_back("caustic, multi-chain perturbations: " + features.specularReason);
        }
        choice.leftOut.push_back(
            "lens-subpath mutation: optional (ALGORITHMS.md 2.5; Mitsuba dropped it for want of a gain); "
            "ask for it with --strategies");
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
            if (e.name == p)
                throw Error("--strategies: '" + e.name + "' is not built yet (available: " + AvailableList + ")");
        if (std::find(std::begin(Available), std::end(Available), e.name) == std::end(Available))
            throw Error("--strategies: unknown strategy '" + e.name + "' (available: " + AvailableList + ")");
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

void makeMutations(const StrategyChoice& choice, const Scene& scene, int maxEdges,
                   std::vector<std::unique_ptr<Mutation>>& owned, std::vector<WeightedMutation>& mix) {
    for (const auto& e : choice.chosen) {
        if (e.name == "bidirectional") owned.push_back(std::make_unique<BidirectionalMutation>(scene, maxEdges));
        if (e.name == "lens") owned.push_back(std::make_unique<LensPerturbation>(scene));
        if (e.name == "caustic") owned.push_back(std::make_unique<CausticPerturbation>(scene));
        if (e.name == "multi-chain") owned.push_back(std::make_unique<MultiChainPerturbation>(scene));
        if (e.name == "lens-subpath") owned.push_back(std::make_unique<LensSubpathMutation>(scene, maxEdges));
        mix.push_back({owned.back().get(), e.weight});
    }
}

} // namespace lt
