// Reading an image file of any format OpenImageIO knows into floats: the one reader of the scene's images
// (bitmap textures, environment maps). Final renders and references go through image/image_io.h.
//
// OpenImageIO brings some 250 shared libraries (codecs, OpenCV, FFmpeg, ...), whose loading and relocation
// took most of a tool's start-up; only scenes with bitmaps need it. So the reader lives in a module of its
// own, lt-image-reader.so (texture/image_reader_module.cpp), loaded on the first image read: a tool that reads
// no image never loads OpenImageIO.
#pragma once

#include <cstdint>
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
// Throws lt::Error "FILE: cannot read image (reason)" for a missing, unreadable or empty image, or when the
// reader module cannot be loaded.
[[nodiscard]] ImageFile readImageFile(const std::string& filename);

// The module's entry point, exported under this name with C linkage: reads `filename` into `image`, or
// returns false with a one-line reason in `error`. No exception leaves the module.
using ImageReaderEntry = bool (*)(const char* filename, ImageFile* image, std::string* error);
inline constexpr const char* kImageReaderEntry = "lt_read_image_file";
inline constexpr const char* kImageReaderModule = "lt-image-reader.so";

// ImageFile and std::string cross the module's boundary, so a module of another build (a copy beside other
// tools, a stale build tree) must not be used unless their layout is the same: it exports
// kImageReaderAbiEntry, which returns kImageReaderAbi as the module was compiled, and the loader takes only a
// module whose value is its own. Raise kImageReaderInterface when the entry point's meaning changes.
using ImageReaderAbi = uint64_t (*)();
inline constexpr const char* kImageReaderAbiEntry = "lt_image_reader_abi";
inline constexpr uint64_t kImageReaderInterface = 1;
inline constexpr uint64_t kImageReaderAbi = kImageReaderInterface << 32 | uint64_t(sizeof(ImageFile)) << 16 |
                                            uint64_t(sizeof(std::string));

} // namespace lt
