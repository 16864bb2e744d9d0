// Per-channel and sample-count statistics of a buffer: what lt-inspect reports about a buffer file,
// and a quick check that a merge or a reconstruction kept the image's level.
#pragma once

#include <optional>
#include <vector>

#include "formats/records.h"
#include "math/summary.h"

namespace lt {

struct BufferStatistics {
    std::vector<Summary> channels;       // one per channel, in the buffer's order
    std::optional<Summary> sampleCounts; // per pixel, when the buffer has them
};

[[nodiscard]] BufferStatistics bufferStatistics(const file::Buffer& buffer);

} // namespace lt
