#include "texture/exr_header.h"

#include <array>

#include <fstream>

#include "math/error.h"
#include "math/memory_budget.h"

namespace lt {

namespace {

// OpenEXR's version field: the format version in the low byte, then flags.
constexpr uint32_t LongNames = 0x400, MultiPart = 0x1000;

class HeaderReader {
public:
    explicit HeaderReader(const std::string& path) : path_(path), in_(path, std::ios::binary) {
        if (!in_) throw Error(path + ": cannot read EXR (no such file, or not readable)");
        in_.seekg(0, std::ios::end);
        size_ = int64_t(in_.tellg());
        in_.seekg(0);
    }

    [[nodiscard]] int64_t left() { return size_ - int64_t(in_.tellg()); }

    void read(void* out, size_t n, const std::string& what) {
        if (int64_t(n) > left() || !in_.read(static_cast<char*>(out), std::streamsize(n)))
            fail("the file ends inside " + what);
    }
    uint32_t u32(const std::string& what) {
        unsigned char b[4];
        read(b, 4, what);
        return uint32_t(b[0]) | uint32_t(b[1]) << 8 | uint32_t(b[2]) << 16 | uint32_t(b[3]) << 24;
    }
    // A null-terminated name of at most `longest` characters.
    std::string name(size_t longest, const std::string& what) {
        std::string text;
        for (char c;;) {
            read(&c, 1, what);
            if (c == '\0') return text;
            if (text.size() == longest) fail(what + " is longer than " + std::to_string(longest) + " characters");
            text += c;
        }
    }
    void skip(int64_t n) { in_.seekg(n, std::ios::cur); }

    [[noreturn]] void fail(const std::string& what) const { throw Error(path_ + ": damaged EXR header: " + what); }

private:
    std::string path_;
    std::ifstream in_;
    int64_t size_ = 0;
};

} // namespace

std::vector<ExrPartLayout> scanExrHeaders(const std::string& path) {
    HeaderReader in(path);
    if (in.u32("the magic number") != 20000630) throw Error(path + ": not an EXR file (no EXR magic number)");
    const uint32_t flags = in.u32("the version field");
    const size_t longest = flags & LongNames ? 255 : 31;
    std::vector<ExrPartLayout> parts;
    do {
        const std::string part = "part " + std::to_string(parts.size() + 1);
        // A multi-part file's headers end with an empty header: a lone null byte.
        std::string attribute = in.name(longest, "an attribute name of " + part);
        if (attribute.empty() && !parts.empty()) break;
        ExrPartLayout layout;
        bool window = false, channels = false;
        for (; !attribute.empty(); attribute = in.name(longest, "an attribute name of " + part)) {
            const std::string what = "attribute '" + attribute + "' of " + part;
            const std::string type = in.name(longest, "the type of " + what);
            const uint32_t size = in.u32("the size of " + what);
            if (int64_t(size) > in.left())
                in.fail(what + " declares " + std::to_string(size) + " bytes, more than the " +
                        std::to_string(in.left()) + " left in the file");
            if (attribute == "dataWindow" && type == "box2i" && size == 16) {
                int32_t box[4];
                for (int32_t& v : box)
                    v = int32_t(in.u32(what));
                if (box[2] < box[0] || box[3] < box[1]) in.fail("the data window of " + part + " is empty");
                layout.width = int64_t(box[2]) - box[0] + 1;
                layout.height = int64_t(box[3]) - box[1] + 1;
                window = true;
            } else if (attribute == "channels" && type == "chlist") {
                // name\0 then pixel type, pLinear, reserved, x and y sampling (16 bytes) per channel; a null ends it.
                int64_t used = 0;
                for (;;) {
                    const std::string channel = in.name(longest, "a channel name of " + part);
                    used += int64_t(channel.size()) + 1;
                    if (channel.empty()) break;
                    char layoutBytes[16];
                    in.read(layoutBytes, 16, "channel '" + channel + "' of " + part);
                    used += 16;
                    ++layout.channels;
                }
                if (used != int64_t(size))
                    in.fail("the channel list of " + part + " does not fill its " + std::to_string(size) + " bytes");
                channels = true;
            } else {
                in.skip(size);
            }
        }
        if (!window) in.fail(part + " has no data window");
        if (!channels) in.fail(part + " has no channel list");
        parts.push_back(layout);
    } while (flags & MultiPart);
    return parts;
}

bool isExrFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::array<char, 4> magic{};
    return in.read(magic.data(), 4) && magic == std::array<char, 4>{0x76, 0x2f, 0x31, 0x01};
}

void requireExrMemory(const std::string& path) {
    double bytes = 0, pixels = 0, channels = 0;
    for (const ExrPartLayout& part : scanExrHeaders(path)) {
        const double n = double(part.width) * double(part.height);
        bytes += n * (4.0 * double(part.channels) + 8.0);
        pixels += n;
        channels += double(part.channels);
    }
    requireMemory(bytes, path + ": an EXR of " + std::to_string(uint64_t(pixels)) + " pixels and " +
                             std::to_string(uint64_t(channels)) + " channels");
}

} // namespace lt
