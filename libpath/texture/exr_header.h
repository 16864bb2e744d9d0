// What an EXR file's headers declare, validated before OpenEXR's C++ library reads the file. That library
// (3.1) allocates an attribute's declared size before reading it, and its chunk offset tables from the data
// window, so a few damaged header bytes ask it for gigabytes (the gradient-input fuzz harness found a 3 KB file
// that made it allocate 1.7 GB). OpenEXR's C core (OpenEXRCore, built to parse untrusted headers) reads them
// first with strict header checks, and what the read will allocate is checked against memory.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace lt {

// One part (one image) of an EXR: its data window, channel count and chunks (scanline blocks or tiles, each
// an 8-byte entry of the offset table).
struct ExrPartLayout {
    int32_t minX = 0, minY = 0;
    int64_t width = 0, height = 0;
    int channels = 0;
    int64_t chunks = 0;
};

// The parts of the EXR at `path`. Throws lt::Error "FILE: damaged EXR header: WHY" when OpenEXRCore refuses
// its headers (an attribute larger than the file, of the wrong size for its type, a missing or empty data
// window, ...).
[[nodiscard]] std::vector<ExrPartLayout> scanExrHeaders(const std::string& path);

// Whether the file starts with the EXR magic number (76 2f 31 01); false if it cannot be read.
[[nodiscard]] bool isExrFile(const std::string& path);

// Throws lt::Error unless reading the EXR at `path` fits in memory (util/memory_budget.h): the parts that share
// the first part's data window as float planes (what image/image_io.h readExr keeps), and every part's offset
// table.
void requireExrMemory(const std::string& path);

} // namespace lt
