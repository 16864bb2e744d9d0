// A pixel estimator as the render tools offer it (`lt-seed --method`, `lt-gradient --method`): a row of the
// estimator registry (run/estimator_registry.h), defined in the estimator's own file: its name, what it is, its own
// options, what it records about itself, and how it is made for a scene. A new estimator is its own files and one
// line of the registry.
#pragma once

#include <nlohmann/json.hpp>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "sampling/path_settings.h"
#include "sampling/pixel_estimator.h"
#include "util/option_spec.h"

namespace lt {

class Scene;

struct EstimatorKind {
    std::string name;                // --method NAME
    std::string summary;             // what it is, for --help
    std::vector<OptionSpec> options; // its own options (their values reach make() and the output's parameters)
    nlohmann::json record;           // what it records of itself besides its options' values
    // Makes the estimator for a scene and the run's path settings.
    std::function<std::unique_ptr<PixelEstimator>(const Scene&, const PathSettings&, const OptionValues&)> make;
    // Optional: a warning for the user about these values (empty: none).
    std::function<std::string(const OptionValues&)> warning;
};

// The option of the estimators that weigh BDPT's or the path tracer's strategies by MIS (Veach thesis ch. 9).
[[nodiscard]] inline OptionSpec misOption() {
    return {"--mis",
            "mis",
            "MIS heuristic: power (default) or balance",
            "TEXT:{power,balance}",
            "power",
            option::choice({"power", "balance"})};
}
// The path settings with the heuristic misOption() chose.
[[nodiscard]] inline PathSettings withMis(PathSettings paths, const OptionValues& values) {
    paths.mis = values.at("mis") == "balance" ? MisHeuristic::Balance : MisHeuristic::Power;
    return paths;
}

} // namespace lt
