#include "image/buffer_statistics.h"

namespace lt {

BufferStatistics bufferStatistics(const file::Buffer& buffer) {
    BufferStatistics s;
    for (const auto& plane : buffer.planes) {
        Summary& c = s.channels.emplace_back();
        for (float v : plane)
            c.add(v);
    }
    if (!buffer.sampleCounts.empty()) {
        s.sampleCounts.emplace();
        for (uint32_t n : buffer.sampleCounts)
            s.sampleCounts->add(n);
    }
    return s;
}

} // namespace lt
