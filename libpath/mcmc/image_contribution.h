// What a Markov-chain state contributes to the image, and the scalar target the chain samples.
#pragma once

#include <algorithm>
#include <vector>

#include "math/spectrum.h"
#include "math/vec.h"

namespace lt {

// A value at a raster position (pixels of the full film), spread over the pixels around it with the
// normalized pixel filter h_j, like a light-tracing splat (image/film.h).
struct ImageContribution {
    Vec2 raster;
    Spectrum value;
};

// The chain's scalar target f* = lum(f) (SURVEY Eq. 16), floored by a small fraction of the largest
// channel so that a colour with zero luminance is still sampled (a target that is 0 where f is not would
// bias the image).
[[nodiscard]] inline double targetValue(const Spectrum& f) { return std::max(f.luminance(), 1e-3 * f.maxValue()); }

[[nodiscard]] inline double targetValue(const std::vector<ImageContribution>& contributions) {
    Spectrum sum;
    for (const auto& c : contributions)
        sum += c.value;
    return targetValue(sum);
}

} // namespace lt
