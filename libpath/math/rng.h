// PCG32 (O'Neill 2014, pcg-random.org, "pcg32" = XSH RR 64/32): small state, independent streams by
// increment, cheap to advance. Every chain and tile gets its own stream so that results do not depend
// on the thread count.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

#include "math/constants.h"

namespace lt {

// SplitMix64's finalizer (Steele et al. 2014): decorrelates consecutive integers (seed, sample index,
// chain index) into PCG32 initial states.
[[nodiscard]] inline uint64_t mixBits(uint64_t x) {
    x += 0x9e3779b97f4a7c15ULL;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
}

class Pcg32 {
public:
    Pcg32() { seed(0x853c49e6748fea9bULL, 0xda3e39cb94b95bdbULL); }
    Pcg32(uint64_t initState, uint64_t stream) { seed(initState, stream); }

    void seed(uint64_t initState, uint64_t stream) {
        state_ = 0;
        inc_ = (stream << 1u) | 1u;
        nextUInt();
        state_ += initState;
        nextUInt();
    }

    uint32_t nextUInt() {
        const uint64_t old = state_;
        state_ = old * 6364136223846793005ULL + inc_;
        const uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
        const uint32_t rot = uint32_t(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31));
    }

    // Uniform in [0, 1): 53 random bits from two draws, never 1.
    double nextDouble() {
        const uint64_t hi = nextUInt(), lo = nextUInt();
        return double(((hi << 32) | lo) >> 11) * 0x1.0p-53;
    }

    // Jump ahead by delta steps in O(log delta) (Brown 1994, "Random number generation with arbitrary
    // strides").
    void advance(uint64_t delta) {
        uint64_t curMult = 6364136223846793005ULL, curPlus = inc_, accMult = 1, accPlus = 0;
        while (delta > 0) {
            if (delta & 1) {
                accMult *= curMult;
                accPlus = accPlus * curMult + curPlus;
            }
            curPlus = (curMult + 1) * curPlus;
            curMult *= curMult;
            delta >>= 1;
        }
        state_ = accMult * state_ + accPlus;
    }

private:
    uint64_t state_ = 0, inc_ = 0;
};

// Two independent standard normal values from two uniforms in [0, 1) by Box-Muller (1 - u keeps the
// logarithm finite): the same numbers on every platform, unlike std::normal_distribution.
[[nodiscard]] inline std::array<double, 2> standardNormalPair(double u, double v) {
    const double r = std::sqrt(-2 * std::log(1 - u));
    return {r * std::cos(TwoPi * v), r * std::sin(TwoPi * v)};
}

// One standard normal draw (the first of the pair).
[[nodiscard]] inline double standardNormal(Pcg32& rng) {
    const double u = rng.nextDouble(), v = rng.nextDouble();
    return standardNormalPair(u, v)[0];
}

} // namespace lt
