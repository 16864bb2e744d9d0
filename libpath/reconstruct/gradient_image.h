// The input of a gradient-domain reconstruction: a noisy RGB primal image, its forward-difference
// gradients and, optionally, the directly visible emitters stored apart (added back after the solve).
// Conventions, shared with the public gradient-domain code so buffers of other renderers can be read:
//   dx(x,y) = I(x+1,y) - I(x,y),  dy(x,y) = I(x,y+1) - I(x,y),  rows top to bottom;
//   the last column of dx and the last row of dy would leave the image and are never read.
// In a buffer (an lt buffer file or a multi-layer EXR) the planes are the channels "primal.R/G/B",
// "dx.R/G/B", "dy.R/G/B" and the optional "direct.R/G/B" (formats/SPEC.md "Gradient-domain channels").
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "formats/records.h"

namespace lt {

// Three planes of width * height values, R, G, B, each row-major with rows top to bottom.
using RgbPlanes = std::array<std::vector<float>, 3>;

struct GradientImage {
    uint32_t width = 0, height = 0;
    RgbPlanes primal, dx, dy;
    std::optional<RgbPlanes> direct; // kept out of the solve and added to its result

    [[nodiscard]] size_t pixels() const { return size_t(width) * height; }
};

// The planes of one buffer holding all layers: "primal.R" ... "dy.B" are required, "direct.R/G/B"
// are optional (all three or none). `name` (the file) starts every error message.
[[nodiscard]] GradientImage gradientImageFromBuffer(const file::Buffer& buffer, const std::string& name);

// One layer of a buffer: channels "LAYER.R/G/B", or, if it has none of those, plain "R", "G", "B" (an
// image with only that layer, e.g. a separate dx.exr). `name` (the file) starts every error message.
[[nodiscard]] RgbPlanes layerFromBuffer(const file::Buffer& buffer, const std::string& layer, const std::string& name);

// A layer from each of separate files (layerFromBuffer), e.g. P.exr, DX.exr, DY.exr, and optionally a
// direct-emission file. Each error names the file it is about: a size that differs from the primal's,
// a missing layer, a NaN or Inf.
struct LayerSource {
    const file::Buffer* buffer = nullptr;
    std::string name;
};
[[nodiscard]] GradientImage gradientImageFromLayers(const LayerSource& primal, const LayerSource& dx,
                                                    const LayerSource& dy, const std::optional<LayerSource>& direct);

// Throws lt::Error naming `name` unless the image is usable: a positive size, every plane width *
// height values, every value finite (a NaN or Inf would spread through the whole solve; one in an
// unused last column or row is still a sign of a broken input). The message gives the channel and the
// first bad pixel.
void validateGradientImage(const GradientImage& image, const std::string& name);

// Forward differences of an image, in the conventions above (0 where a difference would leave the
// image): what a renderer's gradients estimate, for tests and synthetic inputs.
void forwardDifferences(const RgbPlanes& image, uint32_t width, uint32_t height, RgbPlanes& dx, RgbPlanes& dy);

// An R, G, B buffer of the given planes.
[[nodiscard]] file::Buffer rgbBuffer(uint32_t width, uint32_t height, RgbPlanes planes);

} // namespace lt
