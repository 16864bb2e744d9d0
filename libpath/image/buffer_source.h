// The image a file holds, whatever the file: for an lt buffer file its final buffer (the last BUFR, or
// for a run that never wrote one the last snapshot's), for an EXR every channel at weight 1. What the
// tools that develop or compare images (lt-image, lt-error, lt-reconstruct) start from.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

#include "formats/records.h"

namespace lt {

struct BufferSource {
    file::Buffer buffer;
    nlohmann::json info; // the lt file's INFO; empty (null) for an EXR
    std::string name;    // the file as errors name it ("<stdin>" for "-")
    std::string origin;  // where in the file the buffer came from: "BUFR", "SNAP 3 of 3" or "EXR"
};

// An EXR is recognized by its magic number, anything else (and "-", stdin) is read as an lt buffer
// file through lt::file::Reader, whose errors (truncation, damage, wrong kind) pass through unchanged.
[[nodiscard]] BufferSource loadBuffer(const std::string& path);

} // namespace lt
