// The one source of randomness of every path sampler (after Tungsten): BDPT and the path
// tracer draw all their numbers through this interface, so that the primary-sample-space Markov chains
// (PSSMLT, MMLT) can drive the same code unchanged by supplying their own numbers.
#pragma once

#include <cstdint>

#include "math/rng.h"
#include "math/vec.h"

namespace lt {

class SampleGenerator {
public:
    virtual ~SampleGenerator() = default;
    // Kelemen-style samplers keep separate streams for the camera subpath, the light subpath and the
    // connections (pbrt-v3 MLTSampler::StartStream), so a mutation of one leaves the others intact.
    enum Stream : int { CameraStream = 0, LightStream = 1, ConnectStream = 2 };
    virtual void startStream(Stream) {}
    [[nodiscard]] virtual double next1D() = 0;
    // Two numbers that belong together (a direction, a point on a light): a stratified sampler
    // (sampling/sobol_sampler.h) stratifies them jointly. Otherwise two calls of next1D, in that order.
    [[nodiscard]] virtual Vec2 next2D() {
        const double a = next1D();
        return {a, next1D()};
    }
};

// Independent uniform numbers from one PCG32 stream. A sample of pixel (x, y) uses the stream
// seeded by (seed, pixel index) and advanced to its sample index, so results do not depend on how
// the work was split between threads.
class IndependentSampler final : public SampleGenerator {
public:
    IndependentSampler(uint64_t seed, uint64_t stream) : rng_(seed, stream) {}
    [[nodiscard]] double next1D() override { return rng_.nextDouble(); }
    [[nodiscard]] Vec2 next2D() override {
        const double a = rng_.nextDouble();
        return {a, rng_.nextDouble()};
    }
    Pcg32& rng() { return rng_; }

private:
    Pcg32 rng_;
};

} // namespace lt
