#include "image/image_io.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <optional>
#include <set>

#include "math/error.h"
#include "math/temp_output.h"

namespace lt {

namespace {

// The beauty image's channels: R, G, B, or else the first layer X with X.R, X.G, X.B.
std::optional<std::array<size_t, 3>> beautyChannels(const file::Buffer& b) {
    auto find = [&](const std::string& name) -> std::optional<size_t> {
        const auto it = std::find(b.channels.begin(), b.channels.end(), name);
        if (it == b.channels.end()) return std::nullopt;
        return size_t(it - b.channels.begin());
    };
    auto triple = [&](const std::string& prefix) -> std::optional<std::array<size_t, 3>> {
        const auto r = find(prefix + "R"), g = find(prefix + "G"), b = find(prefix + "B");
        if (!r || !g || !b) return std::nullopt;
        return std::array<size_t, 3>{*r, *g, *b};
    };
    if (auto rgb = triple("")) return rgb;
    for (const auto& name : b.channels)
        if (name.size() > 2 && name.ends_with(".R"))
            if (auto rgb = triple(name.substr(0, name.size() - 1))) return rgb;
    return std::nullopt;
}

// Opens `temp` with OpenImageIO's writer for `format` ("openexr", "png"), writes one image and closes
// it; the caller commits the temporary file.
void writeImage(const std::string& format, const TempOutput& temp, const OIIO::ImageSpec& spec, OIIO::TypeDesc type,
                const void* data) {
    auto out = OIIO::ImageOutput::create(format);
    if (!out) throw Error(temp.finalPath() + ": no " + format + " writer (" + OIIO::geterror() + ")");
    if (!out->open(temp.path(), spec) || !out->write_image(type, data) || !out->close())
        throw Error(temp.finalPath() + ": cannot write " + format + " (" + out->geterror() + ")");
}

// sRGB transfer function (IEC 61966-2-1) of a linear value in [0, 1].
double srgbEncode(double v) { return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055; }

} // namespace

void checkBuffer(const file::Buffer& b, const std::string& name) {
    if (b.width == 0 || b.height == 0)
        throw Error(name + ": empty buffer (" + std::to_string(b.width) + "x" + std::to_string(b.height) + ")");
    if (b.channels.empty()) throw Error(name + ": buffer has no channels");
    if (b.planes.size() != b.channels.size())
        throw Error(name + ": buffer has " + std::to_string(b.channels.size()) + " channel names but " +
                    std::to_string(b.planes.size()) + " planes");
    const size_t pixels = size_t(b.width) * size_t(b.height);
    std::set<std::string> seen;
    for (size_t c = 0; c < b.channels.size(); ++c) {
        if (b.channels[c].empty()) throw Error(name + ": buffer channel " + std::to_string(c) + " has no name");
        if (!seen.insert(b.channels[c]).second) throw Error(name + ": buffer channel '" + b.channels[c] + "' twice");
        if (b.planes[c].size() != pixels)
            throw Error(name + ": buffer plane '" + b.channels[c] + "' has " + std::to_string(b.planes[c].size()) +
                        " values, expected " + std::to_string(pixels));
    }
    if (!b.sampleCounts.empty() && b.sampleCounts.size() != pixels)
        throw Error(name + ": buffer has " + std::to_string(b.sampleCounts.size()) + " sample counts, expected " +
                    std::to_string(pixels));
}

void writeExr(const std::string& path, const file::Buffer& buffer, const nlohmann::json& info) {
    checkBuffer(buffer, path);
    // Beauty first: viewers show the first channels, and OpenImageIO reads R, G, B, A first anyway.
    std::vector<size_t> order;
    if (const auto rgb = beautyChannels(buffer); rgb && buffer.channels[(*rgb)[0]] == "R")
        order = {rgb->begin(), rgb->end()};
    for (size_t c = 0; c < buffer.channels.size(); ++c)
        if (std::find(order.begin(), order.end(), c) == order.end()) order.push_back(c);

    OIIO::ImageSpec spec(int(buffer.width), int(buffer.height), int(order.size()), OIIO::TypeDesc::FLOAT);
    spec.channelnames.clear();
    spec.alpha_channel = -1;
    for (size_t i = 0; i < order.size(); ++i) {
        spec.channelnames.push_back(buffer.channels[order[i]]);
        if (buffer.channels[order[i]] == "A") spec.alpha_channel = int(i);
    }
    spec.attribute("compression", "zip");
    spec.attribute("lt:info", info.dump());
    if (info.contains("producer") && info["producer"].is_string())
        spec.attribute("lt:producer", info["producer"].get<std::string>());
    if (info.contains("scene") && info["scene"].is_object()) {
        const auto& scene = info["scene"];
        if (scene.contains("path") && scene["path"].is_string())
            spec.attribute("lt:scene", scene["path"].get<std::string>());
        if (scene.contains("hash") && scene["hash"].is_string())
            spec.attribute("lt:scene_hash", scene["hash"].get<std::string>());
    }

    const size_t pixels = size_t(buffer.width) * size_t(buffer.height);
    std::vector<float> interleaved(pixels * order.size());
    for (size_t i = 0; i < order.size(); ++i) {
        const auto& plane = buffer.planes[order[i]];
        for (size_t p = 0; p < pixels; ++p)
            interleaved[p * order.size() + i] = plane[p];
    }
    TempOutput temp(path);
    writeImage("openexr", temp, spec, OIIO::TypeDesc::FLOAT, interleaved.data());
    temp.commit();
}

void writePng(const std::string& path, const file::Buffer& buffer, double exposureEV) {
    checkBuffer(buffer, path);
    const auto rgb = beautyChannels(buffer);
    if (!rgb) throw Error(path + ": no R, G, B channels (nor a layer with them) to preview");
    const double scale = std::exp2(exposureEV);
    const size_t pixels = size_t(buffer.width) * size_t(buffer.height);
    std::vector<uint8_t> bytes(pixels * 3);
    for (size_t p = 0; p < pixels; ++p)
        for (size_t c = 0; c < 3; ++c) {
            const double v = double(buffer.planes[(*rgb)[c]][p]) * scale;
            // !(v > 0) also catches NaN: black, not garbage, for a pixel a bug left undefined.
            const double clamped = !(v > 0) ? 0.0 : std::min(v, 1.0);
            bytes[p * 3 + c] = uint8_t(std::lround(255 * srgbEncode(clamped)));
        }
    OIIO::ImageSpec spec(int(buffer.width), int(buffer.height), 3, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:ColorSpace", "sRGB");
    TempOutput temp(path);
    writeImage("png", temp, spec, OIIO::TypeDesc::UINT8, bytes.data());
    temp.commit();
}

file::Buffer readExr(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw Error(path + ": cannot read EXR (" + OIIO::geterror() + ")");
    if (std::string(in->format_name()) != "openexr")
        throw Error(path + ": not an EXR file (it is " + std::string(in->format_name()) + ")");
    file::Buffer b;
    const OIIO::ImageSpec first = in->spec();
    b.width = uint32_t(first.width);
    b.height = uint32_t(first.height);
    const size_t pixels = size_t(b.width) * size_t(b.height);
    for (int part = 0; in->seek_subimage(part, 0); ++part) {
        const OIIO::ImageSpec& spec = in->spec();
        if (spec.deep) throw Error(path + ": deep EXR data is not supported");
        // Parts of another data window are other images (e.g. a preview), not planes of this one.
        if (spec.x != first.x || spec.y != first.y || spec.width != first.width || spec.height != first.height)
            continue;
        const size_t n = size_t(spec.nchannels);
        std::vector<float> data(pixels * n);
        if (!in->read_image(part, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, data.data()))
            throw Error(path + ": cannot read EXR (" + in->geterror() + ")");
        const std::string partName = spec.get_string_attribute("oiio:subimagename");
        for (size_t c = 0; c < n; ++c) {
            std::string name = spec.channelnames[c];
            if (std::find(b.channels.begin(), b.channels.end(), name) != b.channels.end() && !partName.empty())
                name = partName + "." + name;
            std::vector<float> plane(pixels);
            for (size_t p = 0; p < pixels; ++p)
                plane[p] = data[p * n + c];
            b.channels.push_back(std::move(name));
            b.planes.push_back(std::move(plane));
        }
    }
    checkBuffer(b, path);
    return b;
}

bool isExrFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::array<char, 4> magic{};
    return in.read(magic.data(), 4) && magic == std::array<char, 4>{0x76, 0x2f, 0x31, 0x01};
}

} // namespace lt
