#include "image/image_io.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputPart.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfStdIO.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <png.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <optional>
#include <set>
#include <tuple>

#include "util/error.h"
#include "util/one_line.h"
#include "util/temp_output.h"
#include "texture/exr_header.h"

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

// The order a reader presents an EXR's channels in (the file keeps them sorted by name): the beauty layer
// first, then the other layers as the file has them, and within each layer R, G, B, A before the rest, as
// viewers and OpenImageIO show them.
bool exrChannelBefore(const std::string& a, const std::string& b) {
    auto key = [](const std::string& name) {
        const size_t dot = name.rfind('.');
        const std::string layer = dot == std::string::npos ? "" : name.substr(0, dot);
        const std::string suffix = dot == std::string::npos ? name : name.substr(dot + 1);
        static const std::array<std::string, 4> first = {"R", "G", "B", "A"};
        const size_t rank = size_t(std::find(first.begin(), first.end(), suffix) - first.begin());
        return std::tuple(!layer.empty(), layer, rank, suffix);
    };
    return key(a) < key(b);
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
    // An EXR file keeps its channels sorted by name; readers put R, G, B first (readExr does).
    Imf::Header header(int(buffer.width), int(buffer.height));
    header.compression() = Imf::ZIP_COMPRESSION;
    header.insert("lt:info", Imf::StringAttribute(info.dump()));
    if (info.contains("producer") && info["producer"].is_string())
        header.insert("lt:producer", Imf::StringAttribute(info["producer"].get<std::string>()));
    if (info.contains("scene") && info["scene"].is_object()) {
        const auto& scene = info["scene"];
        if (scene.contains("path") && scene["path"].is_string())
            header.insert("lt:scene", Imf::StringAttribute(scene["path"].get<std::string>()));
        if (scene.contains("hash") && scene["hash"].is_string())
            header.insert("lt:scene_hash", Imf::StringAttribute(scene["hash"].get<std::string>()));
    }
    // The planes are written in place, one slice each (rows top to bottom, as the buffer stores them).
    Imf::FrameBuffer frame;
    for (size_t c = 0; c < buffer.channels.size(); ++c) {
        header.channels().insert(buffer.channels[c], Imf::Channel(Imf::FLOAT));
        frame.insert(buffer.channels[c],
                     Imf::Slice(Imf::FLOAT, const_cast<char*>(reinterpret_cast<const char*>(buffer.planes[c].data())),
                                sizeof(float), sizeof(float) * size_t(buffer.width)));
    }
    TempOutput temp(path);
    // Our own stream: OutputFile's destructor writes the line offsets and swallows any failure there (a full
    // disk at the end), which only the stream's state then shows.
    std::ofstream file(temp.path(), std::ios::binary);
    try {
        Imf::StdOFStream stream(file, temp.path().c_str());
        Imf::OutputFile out(stream, header);
        out.setFrameBuffer(frame);
        out.writePixels(int(buffer.height));
    } catch (const std::exception& e) {
        throw Error(path + ": cannot write EXR (" + oneLine(e.what()) + ")");
    }
    file.close();
    if (!file) throw Error(path + ": cannot write EXR (writing " + temp.path() + " failed: is the disk full?)");
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
    // libpng's simplified writer: 8-bit RGB, marked sRGB.
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    image.width = buffer.width;
    image.height = buffer.height;
    image.format = PNG_FORMAT_RGB;
    TempOutput temp(path);
    if (!png_image_write_to_file(&image, temp.path().c_str(), 0, bytes.data(), 0, nullptr))
        throw Error(path + ": cannot write PNG (" + std::string(image.message) + ")");
    temp.commit();
}

file::Buffer readExr(const std::string& path) {
    if (!std::ifstream(path, std::ios::binary)) throw Error(path + ": cannot read EXR (no such file, or not readable)");
    if (!isExrFile(path)) throw Error(path + ": not an EXR file (no EXR magic number)");
    file::Buffer b;
    try {
        requireExrMemory(path); // before OpenEXR allocates what the header declares
        Imf::MultiPartInputFile file(path.c_str());
        const Imath::Box2i first = file.header(0).dataWindow();
        b.width = uint32_t(first.max.x - first.min.x + 1);
        b.height = uint32_t(first.max.y - first.min.y + 1);
        const size_t pixels = size_t(b.width) * size_t(b.height);
        for (int part = 0; part < file.parts(); ++part) {
            const Imf::Header& header = file.header(part);
            if (header.hasType() && Imf::isDeepData(header.type()))
                throw Error(path + ": deep EXR data is not supported");
            // Parts of another data window are other images (e.g. a preview), not planes of this one.
            if (header.dataWindow() != first) continue;
            const std::string partName = header.hasName() ? header.name() : "";
            std::vector<std::string> names;
            for (auto it = header.channels().begin(); it != header.channels().end(); ++it)
                names.emplace_back(it.name());
            std::stable_sort(names.begin(), names.end(), exrChannelBefore);
            // Every channel read as float (half and unsigned int convert), one plane each.
            Imf::FrameBuffer frame;
            const size_t firstNew = b.planes.size();
            for (const auto& name : names) {
                std::vector<float>& plane = b.planes.emplace_back(pixels);
                frame.insert(name, Imf::Slice::Make(Imf::FLOAT, plane.data(), first, sizeof(float),
                                                    sizeof(float) * size_t(b.width)));
            }
            Imf::InputPart in(file, part);
            in.setFrameBuffer(frame);
            in.readPixels(first.min.y, first.max.y);
            for (size_t c = 0; c < names.size(); ++c) {
                std::string name = names[c];
                if (std::find(b.channels.begin(), b.channels.begin() + std::ptrdiff_t(firstNew), name) !=
                        b.channels.begin() + std::ptrdiff_t(firstNew) &&
                    !partName.empty())
                    name = partName + "." + name;
                b.channels.push_back(std::move(name));
            }
        }
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        throw Error(path + ": cannot read EXR (" + oneLine(e.what()) + ")");
    }
    checkBuffer(b, path);
    return b;
}

} // namespace lt
