#include "reconstruct/gradient_image.h"

#include <algorithm>
#include <cmath>

#include "image/image_io.h"
#include "util/error.h"

namespace lt {

namespace {

constexpr std::array<const char*, 3> kRgb{"R", "G", "B"};

const std::vector<float>* findChannel(const file::Buffer& buffer, const std::string& channel) {
    const auto it = std::find(buffer.channels.begin(), buffer.channels.end(), channel);
    return it == buffer.channels.end() ? nullptr : &buffer.planes[size_t(it - buffer.channels.begin())];
}

// The planes "LAYER.R/G/B" if the buffer has all of them, nullopt if it has none; some but not all is
// an error.
std::optional<RgbPlanes> findLayer(const file::Buffer& buffer, const std::string& layer, const std::string& name) {
    RgbPlanes planes;
    int found = 0;
    std::string missing;
    for (size_t c = 0; c < 3; ++c) {
        const std::string channel = layer + "." + kRgb[c];
        if (const auto* plane = findChannel(buffer, channel)) {
            planes[c] = *plane;
            ++found;
        } else {
            missing += (missing.empty() ? "" : ", ") + channel;
        }
    }
    if (found == 0) return std::nullopt;
    if (found < 3) throw Error(name + ": layer '" + layer + "' is incomplete: no channel " + missing);
    return planes;
}

void checkSize(uint32_t width, uint32_t height, const std::string& name) {
    if (width == 0 || height == 0)
        throw Error(name + ": empty image (" + std::to_string(width) + "x" + std::to_string(height) + ")");
}

// Every plane of the layer width * height values, all finite.
void checkPlanes(const RgbPlanes& planes, const char* layer, uint32_t width, uint32_t height, const std::string& name) {
    const size_t pixels = size_t(width) * height;
    for (size_t c = 0; c < 3; ++c) {
        const std::string channel = std::string(layer) + "." + kRgb[c];
        if (planes[c].size() != pixels)
            throw Error(name + ": channel " + channel + " has " + std::to_string(planes[c].size()) + " values, the " +
                        std::to_string(width) + "x" + std::to_string(height) + " image needs " +
                        std::to_string(pixels));
        const auto bad = std::find_if(planes[c].begin(), planes[c].end(), [](float v) { return !std::isfinite(v); });
        if (bad != planes[c].end()) {
            const size_t p = size_t(bad - planes[c].begin());
            throw Error(name + ": channel " + channel + " is " + (std::isnan(*bad) ? "NaN" : "infinite") +
                        " at pixel (" + std::to_string(p % width) + ", " + std::to_string(p / width) + ")");
        }
    }
}

std::string channelList(const file::Buffer& buffer) {
    std::string list;
    for (const auto& c : buffer.channels)
        list += (list.empty() ? "" : ", ") + c;
    return list.empty() ? "none" : list;
}

} // namespace

RgbPlanes layerFromBuffer(const file::Buffer& buffer, const std::string& layer, const std::string& name) {
    checkBuffer(buffer, name);
    if (auto planes = findLayer(buffer, layer, name)) return std::move(*planes);
    RgbPlanes rgb;
    for (size_t c = 0; c < 3; ++c) {
        const auto* plane = findChannel(buffer, kRgb[c]);
        if (!plane)
            throw Error(name + ": no layer '" + layer + "' (channels " + layer + ".R/G/B, or R, G, B); it has " +
                        channelList(buffer));
        rgb[c] = *plane;
    }
    return rgb;
}

GradientImage gradientImageFromBuffer(const file::Buffer& buffer, const std::string& name) {
    checkBuffer(buffer, name);
    GradientImage image;
    image.width = buffer.width;
    image.height = buffer.height;
    for (const auto& [layer, planes] :
         {std::pair{"primal", &image.primal}, std::pair{"dx", &image.dx}, std::pair{"dy", &image.dy}}) {
        auto found = findLayer(buffer, layer, name);
        if (!found)
            throw Error(name + ": no layer '" + layer + "' (channels " + layer + ".R/G/B); it has " +
                        channelList(buffer));
        *planes = std::move(*found);
    }
    image.direct = findLayer(buffer, "direct", name);
    validateGradientImage(image, name);
    return image;
}

void validateGradientImage(const GradientImage& image, const std::string& name) {
    checkSize(image.width, image.height, name);
    checkPlanes(image.primal, "primal", image.width, image.height, name);
    checkPlanes(image.dx, "dx", image.width, image.height, name);
    checkPlanes(image.dy, "dy", image.width, image.height, name);
    if (image.direct) checkPlanes(*image.direct, "direct", image.width, image.height, name);
}

GradientImage gradientImageFromLayers(const LayerSource& primal, const LayerSource& dx, const LayerSource& dy,
                                      const std::optional<LayerSource>& direct) {
    GradientImage image;
    image.width = primal.buffer->width;
    image.height = primal.buffer->height;
    checkSize(image.width, image.height, primal.name);
    const auto load = [&](const LayerSource& source, const char* layer) {
        const file::Buffer& b = *source.buffer;
        if (b.width != image.width || b.height != image.height)
            throw Error(source.name + ": " + std::to_string(b.width) + "x" + std::to_string(b.height) +
                        " does not match the primal " + primal.name + " (" + std::to_string(image.width) + "x" +
                        std::to_string(image.height) + ")");
        RgbPlanes planes = layerFromBuffer(b, layer, source.name);
        checkPlanes(planes, layer, image.width, image.height, source.name);
        return planes;
    };
    image.primal = load(primal, "primal");
    image.dx = load(dx, "dx");
    image.dy = load(dy, "dy");
    if (direct) image.direct = load(*direct, "direct");
    return image;
}

void forwardDifferences(const RgbPlanes& image, uint32_t width, uint32_t height, RgbPlanes& dx, RgbPlanes& dy) {
    for (size_t c = 0; c < 3; ++c) {
        const auto& I = image[c];
        dx[c].assign(I.size(), 0.0f);
        dy[c].assign(I.size(), 0.0f);
        for (uint32_t y = 0; y < height; ++y)
            for (uint32_t x = 0; x < width; ++x) {
                const size_t p = size_t(y) * width + x;
                if (x + 1 < width) dx[c][p] = I[p + 1] - I[p];
                if (y + 1 < height) dy[c][p] = I[p + width] - I[p];
            }
    }
}

file::Buffer rgbBuffer(uint32_t width, uint32_t height, RgbPlanes planes) {
    file::Buffer b;
    b.width = width;
    b.height = height;
    b.channels = {"R", "G", "B"};
    for (auto& plane : planes)
        b.planes.push_back(std::move(plane));
    return b;
}

} // namespace lt
