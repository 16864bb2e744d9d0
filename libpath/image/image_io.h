// Sample buffers to and from image files: a linear float EXR with every plane as a channel and the file's
// INFO as metadata (the exchange format for final images; OpenEXR), an 8-bit sRGB PNG preview (libpng), and
// reading any EXR back into a buffer (ours, or one another renderer wrote). Neither needs OpenImageIO, which
// only the scene's bitmap textures load (texture/image_file.h): a tool starts without its libraries.
// Writes go to a temporary name renamed when complete; every error is an lt::Error naming the file.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

#include "formats/records.h"
#include "texture/exr_header.h" // isExrFile

namespace lt {

// Throws unless `buffer` is well formed: a positive size, as many planes as channel names, unique
// non-empty names, every plane width * height values. `name` (the file it is for) starts the message.
void checkBuffer(const file::Buffer& buffer, const std::string& name);

// Linear float EXR. Channels keep their names, so "dx.R" is channel R of layer "dx"; R, G, B (the
// beauty image) come first. Metadata: the whole INFO JSON as the string attribute "lt:info", plus
// "lt:producer", "lt:scene" and "lt:scene_hash" when INFO has them (readable without a JSON parser).
void writeExr(const std::string& path, const file::Buffer& buffer, const nlohmann::json& info);

// 8-bit sRGB preview of the beauty image: channels R, G, B (or, without them, the first layer that has
// X.R, X.G, X.B) scaled by 2^exposureEV, clamped to [0, 1]; NaN and negative values become black.
void writePng(const std::string& path, const file::Buffer& buffer, double exposureEV);

// Every channel of an EXR file as a buffer of weight 1 (combine "weighted-mean", no sample counts), in
// float whatever the file stores, the beauty layer first and R, G, B, A first in each layer.
// The data window is the image; parts of a multi-part file with the data window of the first are added
// as further channels, prefixed with the part's name where they would repeat a name.
[[nodiscard]] file::Buffer readExr(const std::string& path);

} // namespace lt
