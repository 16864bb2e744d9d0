// Combining the buffers of several files by their stored weights (formats/SPEC.md "Combining the
// buffers of several files"): independent runs with different seeds, chains, or machines that each
// did part of the work.
#pragma once

#include <span>
#include <string>

#include "formats/records.h"

namespace lt {

// Plane by plane and pixel by pixel: "weighted-mean" gives sum_i w_i x_i / sum_i w_i, "sum" gives
// sum_i x_i; the result's weight is sum_i w_i, sample counts add where every buffer has them. Planes
// are matched by channel name (EXR readers may order them differently), in the first buffer's order.
// `names` (the files, one per buffer) make the errors: different sizes, channel sets or combine
// rules, or a weighted mean of total weight 0, each name both files involved. A single buffer is
// returned as it is.
[[nodiscard]] file::Buffer mergeBuffers(std::span<const file::Buffer> buffers, std::span<const std::string> names);

} // namespace lt
