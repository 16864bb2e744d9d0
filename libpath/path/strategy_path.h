// One joined path as a bidirectional strategy (s, t) produced it: the view of it that seed-path output,
// path records and inspection need, without the sampler that made it.
#pragma once

#include <functional>
#include <vector>

#include "math/spectrum.h"
#include "math/vec.h"
#include "path/vertex.h"

namespace lt {

struct StrategyPath {
    int s = 0, t = 0;
    const std::vector<PathVertex>* light = nullptr;  // light subpath, the first s vertices used
    const std::vector<PathVertex>* camera = nullptr; // camera subpath, the first t vertices used
    const PathVertex* sampled = nullptr;             // the vertex that replaced light[0] (s = 1) or camera[0] (t = 1)
    Vec2 raster;
    Spectrum unweighted; // f / p of the strategy
    double misWeight = 0;
};
using StrategyCallback = std::function<void(const StrategyPath&)>;

} // namespace lt
