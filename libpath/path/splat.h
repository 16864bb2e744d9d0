// A contribution that lands away from the sample's own pixel: light tracing (t = 1) and every Markov-chain
// state are recorded at a raster position, and the film spreads them over the pixels whose filter covers it.
#pragma once

#include "math/spectrum.h"
#include "math/vec.h"

namespace lt {

struct Splat {
    Vec2 raster; // pixels of the full film
    Spectrum value;
};

} // namespace lt
