// Reading an image file of any format OpenImageIO knows into floats: the one reader of the scene's images
// (bitmap textures, environment maps). Final renders and references go through image/image_io.h.
#pragma once

#include <string>
#include <vector>

namespace lt {

struct ImageFile {
    int width = 0, height = 0, channels = 0;
    std::vector<std::string> channelNames; // as the file names them ("R", "G", "B", "A", "Y", ...)
    std::vector<float> pixels; // width * height * channels, rows top to bottom, as stored
    bool floatFormat = false;  // stored as floating point (EXR, HDR, PFM): linear by convention
    bool saysLinear = false;   // the file's colour space says linear
};

// Colours are kept as stored, alpha not applied (OpenImageIO would premultiply; Mitsuba drops alpha).
// Throws lt::Error "FILE: cannot read image (reason)" for a missing, unreadable or empty image.
[[nodiscard]] ImageFile readImageFile(const std::string& filename);

} // namespace lt
