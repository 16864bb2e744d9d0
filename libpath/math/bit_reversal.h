// The binary digits of a 32-bit word in reverse order: as a fraction, van der Corput's radical inverse in
// base 2 of the index (the first component of Sobol's sequence and of the Hammersley points).
#pragma once

#include <cstdint>

namespace lt {

[[nodiscard]] inline uint32_t reverseBits(uint32_t x) {
    x = __builtin_bswap32(x);
    x = ((x & 0x0f0f0f0fu) << 4) | ((x & 0xf0f0f0f0u) >> 4);
    x = ((x & 0x33333333u) << 2) | ((x & 0xccccccccu) >> 2);
    return ((x & 0x55555555u) << 1) | ((x & 0xaaaaaaaau) >> 1);
}

} // namespace lt
