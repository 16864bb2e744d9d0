// Stratified random numbers for the pixel estimators: padded, shuffled, Owen-scrambled Sobol' points
// (Burley 2020, "Practical Hash-based Owen Scrambling", JCGT 9(4)).
//
// The samples of one pixel are the points of one sequence, sample index = point index. Each call of
// next1D or next2D takes the next "slot" of the sample and gets its own copy of the first one or two
// dimensions of Sobol's sequence (a (0, 2)-sequence), with the point index shuffled and the point
// Owen-scrambled by seeds hashed from (seed, pixel, slot). So within every slot the first 2^m samples of a
// pixel form a (0, m, 2)-net: the lens position, each light sample and each BSDF direction are stratified
// over the pixel's samples, whatever the number of slots a path uses (no table of direction numbers, no
// dimension limit), while the shuffles keep different slots, and different pixels, uncorrelated. A 2D
// sample keeps its stratification only if it is drawn with next2D, one slot for both numbers.
//
// Every sample alone is uniform on the unit hypercube (each hashed scramble acts as a random permutation of
// the digits), so every estimator stays unbiased; only the variance over a pixel's samples changes.
#pragma once

#include <cstdint>

#include "sampling/sample_generator.h"

namespace lt {

// The first two dimensions of Sobol's sequence as 32-bit binary fractions: the van der Corput radical
// inverse and Sobol's second component, whose generator matrix is Pascal's triangle mod 2 (Kollig and
// Keller 2002, "Efficient Multidimensional Sampling"). Together a (0, 2)-sequence in base 2:
// every aligned block of 2^m consecutive points is a (0, m, 2)-net.
[[nodiscard]] uint32_t sobolComponent0(uint32_t index);
[[nodiscard]] uint32_t sobolComponent1(uint32_t index);

// Owen's nested uniform scramble of a 32-bit binary fraction by a hash (Burley 2020, after Laine and Karras
// 2011): digit k is flipped by a function of the seed and of digits 1 .. k-1 only, so each elementary
// interval maps onto one of the same size and a (0, m, 2)-net stays one. Applied to a point index (Burley's
// shuffle), it maps every aligned block of 2^m indices onto an aligned block of 2^m, in a scrambled order:
// the first 2^m samples of a pixel are then one aligned block of the (0, 2)-sequence, a net.
[[nodiscard]] uint32_t owenScramble(uint32_t x, uint32_t seed);

class SobolSampler final : public SampleGenerator {
public:
    // Sample `index` of `pixel` (any key that tells pixels apart) under `seed`.
    SobolSampler(uint64_t seed, uint64_t pixel, uint32_t index);
    [[nodiscard]] double next1D() override;
    [[nodiscard]] Vec2 next2D() override;

private:
    uint64_t key_;           // hashed (seed, pixel): the slots' seeds derive from it
    uint32_t reversedIndex_; // the sample's point index, digits reversed
    uint64_t slot_ = 0;
};

} // namespace lt
