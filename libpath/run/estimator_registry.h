// Every pixel estimator the render tools offer, in one table (a row per estimator, defined in its own file:
// sampling/estimator_kind.h): lt-seed offers BDPT and the path tracer, lt-gradient the gradient-domain ones.
#pragma once

#include <nlohmann/json.hpp>

#include <span>
#include <string>
#include <vector>

#include "sampling/estimator_kind.h"

namespace lt {

using EstimatorKinds = std::span<const EstimatorKind* const>;

// The registry: bdpt, pt, gdpr, gpt.
[[nodiscard]] EstimatorKinds estimatorKinds();
// The rows named in `names`, in that order; throws lt::Error for a name the registry lacks.
[[nodiscard]] std::vector<const EstimatorKind*> estimatorKinds(const std::vector<std::string>& names);

// What a run records of its estimator: its record and the values of its options (their defaults where not given).
[[nodiscard]] nlohmann::json estimatorParameters(const EstimatorKind& kind, OptionValues values);

} // namespace lt
