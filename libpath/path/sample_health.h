// Counts of samples that produced NaN or Inf and were dropped: they never reach an output, and the tools
// report how many there were.
#pragma once

#include <cstdint>

namespace lt {

struct SampleHealth {
    uint64_t nonFinite = 0;
};

} // namespace lt
