#include "sampling/sobol_sampler.h"

#include "math/bit_reversal.h"
#include "math/rng.h"

namespace lt {

namespace {

// Owen's scramble on the REVERSED digits of a fraction (leading digit in bit 0): addition and xor with a
// multiple by an even constant change bit k only as a function of the bits below it, the hierarchy of Owen's
// scramble (Burley 2020's hash and constants).
uint32_t scrambleReversed(uint32_t r, uint32_t seed) {
    r += seed;
    r ^= r * 0x6c50b47cu;
    r ^= r * 0xb82f1e52u;
    r ^= r * 0xc7afe638u;
    r ^= r * 0x8d22f6e6u;
    return r;
}

// Sobol's second component with reversed digits, a byte of the index at a time: the xor of the generator
// matrix's columns v_k for the index's set bits k, where v_0 = 1/2 and v_{k+1} = v_k xor (v_k >> 1) (column k
// is row k of Pascal's triangle mod 2), each column stored reversed.
struct PascalColumns {
    uint32_t byByte[4][256];
    PascalColumns() {
        uint32_t v[32];
        v[0] = 1u << 31;
        for (int k = 1; k < 32; ++k)
            v[k] = v[k - 1] ^ (v[k - 1] >> 1);
        for (int b = 0; b < 4; ++b)
            for (uint32_t byte = 0; byte < 256; ++byte) {
                uint32_t x = 0;
                for (int j = 0; j < 8; ++j)
                    if (byte & (1u << j)) x ^= reverseBits(v[8 * b + j]);
                byByte[b][byte] = x;
            }
    }
};

const PascalColumns columns; // 4 KiB, made before main

uint32_t sobolComponent1Reversed(uint32_t index) {
    return columns.byByte[0][index & 0xffu] ^ columns.byByte[1][(index >> 8) & 0xffu] ^
           columns.byByte[2][(index >> 16) & 0xffu] ^ columns.byByte[3][index >> 24];
}

// A 32-bit fraction x plus 16 more bits `jitter` below its last digit, as a double in [0, 1): the point stays in
// its finest stratum, and its resolution (2^-48) is that of a double rather than 2^-32, as the independent
// sampler's numbers. The largest value is 1 - 2^-48.
double toUnit(uint32_t x, uint32_t jitter) { return (double(x) + double(jitter & 0xffffu) * 0x1p-16) * 0x1p-32; }

} // namespace

uint32_t sobolComponent0(uint32_t index) { return reverseBits(index); }

uint32_t sobolComponent1(uint32_t index) { return reverseBits(sobolComponent1Reversed(index)); }

uint32_t owenScramble(uint32_t x, uint32_t seed) { return reverseBits(scrambleReversed(reverseBits(x), seed)); }

// Below, the compositions owenScramble(sobolComponentK(owenScramble(index, s0)), sK) with the reversals that
// cancel left out: owenScramble(index, s0) = reverse(scrambleReversed(reversedIndex_, s0)) = point;
// owenScramble(sobolComponent0(point), s1) = reverse(scrambleReversed(point, s1)), as sobolComponent0 is a reversal;
// owenScramble(sobolComponent1(point), s2) = reverse(scrambleReversed(sobolComponent1Reversed(point), s2)).
SobolSampler::SobolSampler(uint64_t seed, uint64_t pixel, uint32_t index)
    : key_(mixBits(mixBits(seed ^ 0x50b01ULL) + pixel)), reversedIndex_(reverseBits(index)) {}

double SobolSampler::next1D() {
    const uint64_t h = mixBits(key_ + slot_++);
    const uint32_t point = reverseBits(scrambleReversed(reversedIndex_, uint32_t(h)));
    return toUnit(reverseBits(scrambleReversed(point, uint32_t(h >> 32))), uint32_t(mixBits(h)));
}

Vec2 SobolSampler::next2D() {
    const uint64_t h = mixBits(key_ + slot_++);
    const uint64_t g = mixBits(h);
    const uint32_t point = reverseBits(scrambleReversed(reversedIndex_, uint32_t(h)));
    return {toUnit(reverseBits(scrambleReversed(point, uint32_t(h >> 32))), uint32_t(g >> 32)),
            toUnit(reverseBits(scrambleReversed(sobolComponent1Reversed(point), uint32_t(g))), uint32_t(g >> 48))};
}

} // namespace lt
