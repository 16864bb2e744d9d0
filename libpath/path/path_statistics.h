// What a set of stored paths looks like at a glance: how long they are, which BDPT techniques made
// them, how their resampling weights spread. lt-inspect prints it; a seed-selection or chain tool can
// use it to check what a paths file covers before starting.
#pragma once

#include <cstddef>
#include <map>
#include <span>
#include <utility>

#include "formats/records.h"
#include "math/summary.h"

namespace lt {

struct PathStatistics {
    size_t count = 0;
    std::map<size_t, size_t> lengths;                 // path length in edges -> number of paths
    std::map<std::pair<int, int>, size_t> techniques; // BDPT technique (s, t) -> number of paths
    Summary weight;                                   // resampling weights
};

[[nodiscard]] PathStatistics pathStatistics(std::span<const file::PathRecord> paths);

} // namespace lt
