// What an EXR file's headers declare, read with every size checked against the file before OpenEXR sees it.
// OpenEXR 3.1 allocates an attribute's declared size before reading it, and its chunk offset tables from the
// data window, so a few damaged header bytes ask it for gigabytes (the gradient-input fuzz harness found a
// 3 KB file that made it allocate 1.7 GB): readers check this layout, and its memory, first (image/image_io.h
// readExr, and texture/image_file.h for a bitmap or an environment map in EXR).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace lt {

// One part (one image) of an EXR: its data window's size and its channel count.
struct ExrPartLayout {
    int64_t width = 0, height = 0;
    size_t channels = 0;
};

// The parts of the EXR at `path` (one for a single-part file), from the attribute layout of OpenEXR's file
// format: magic, version and flags, then per part name\0 type\0 size:i32 value[size] ... \0, a multi-part
// file's list of headers ending in an empty one. Throws lt::Error naming the file when the file is not an EXR,
// an attribute is cut short or declares more bytes than the file holds, a part has no data window or channel
// list, or its data window is empty.
[[nodiscard]] std::vector<ExrPartLayout> scanExrHeaders(const std::string& path);

// Whether the file starts with the EXR magic number (76 2f 31 01); false if it cannot be read.
[[nodiscard]] bool isExrFile(const std::string& path);

// Throws lt::Error unless the memory of reading the EXR at `path` fits (math/memory_budget.h): every part's
// pixels as float channels plus OpenEXR's offset tables (8 bytes a chunk, at most one chunk a pixel).
void requireExrMemory(const std::string& path);

} // namespace lt
