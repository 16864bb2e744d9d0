// loadPly: the Stanford PLY format, read by hand (Debian packages no small PLY library; assimp is far too
// heavy for one format). Format reference: Greg Turk, "The PLY Polygon File Format" (1994), and the
// conventions of Mitsuba 0.5's `ply` shape plugin (src/shapes/ply.cpp): vertex properties x y z,
// nx ny nz, and u v / s t / texture_u texture_v; faces as a list property `vertex_indices` (or
// `vertex_index`); texture coordinates used as stored (no vertical flip, unlike OBJ).
#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <optional>
#include <sstream>
#include <string_view>
#include <system_error>

#include "util/error.h"
#include "scene/mesh.h"

namespace lt {
namespace {

enum class Scalar { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };
enum class Format { Ascii, BinaryLittleEndian, BinaryBigEndian };

std::optional<Scalar> parseScalar(std::string_view name) {
    // The 1994 names and the sized aliases that later writers (e.g. VTK, Open3D) use.
    if (name == "char" || name == "int8") return Scalar::Int8;
    if (name == "uchar" || name == "uint8") return Scalar::UInt8;
    if (name == "short" || name == "int16") return Scalar::Int16;
    if (name == "ushort" || name == "uint16") return Scalar::UInt16;
    if (name == "int" || name == "int32") return Scalar::Int32;
    if (name == "uint" || name == "uint32") return Scalar::UInt32;
    if (name == "float" || name == "float32") return Scalar::Float32;
    if (name == "double" || name == "float64") return Scalar::Float64;
    return std::nullopt;
}

size_t sizeOf(Scalar type) {
    switch (type) {
    case Scalar::Int8:
    case Scalar::UInt8:
        return 1;
    case Scalar::Int16:
    case Scalar::UInt16:
        return 2;
    case Scalar::Int32:
    case Scalar::UInt32:
    case Scalar::Float32:
        return 4;
    case Scalar::Float64:
        return 8;
    }
    return 0;
}

bool isInteger(Scalar type) {
    return type != Scalar::Float32 && type != Scalar::Float64;
}

struct Property {
    std::string name;
    Scalar type = Scalar::Float32; // of the value, or of each list entry
    std::optional<Scalar> listCount;
};

struct Element {
    std::string name;
    uint64_t count = 0;
    std::vector<Property> properties;
};

struct Header {
    Format format = Format::Ascii;
    std::vector<Element> elements;
    size_t dataOffset = 0; // first byte after the end_header line
    size_t lineCount = 0;  // lines in the header, for ASCII line numbers
};

std::string readWholeFile(const std::string &filename) {
    std::ifstream in(filename, std::ios::binary);
    if (!in) throw Error(filename + ": cannot open file (" + std::generic_category().message(errno) + ")");
    std::ostringstream data;
    data << in.rdbuf();
    if (in.bad()) throw Error(filename + ": cannot read file");
    return data.str();
}

std::vector<std::string_view> splitWords(std::string_view line) {
    std::vector<std::string_view> words;
    size_t pos = 0;
    while ((pos = line.find_first_not_of(" \t\r", pos)) != std::string_view::npos) {
        const size_t end = std::min(line.find_first_of(" \t\r", pos), line.size());
        words.push_back(line.substr(pos, end - pos));
        pos = end;
    }
    return words;
}

Header parseHeader(const std::string &data, const std::string &filename) {
    Header header;
    bool sawFormat = false;
    size_t pos = 0;
    for (size_t lineNumber = 1;; ++lineNumber) {
        const size_t end = data.find('\n', pos);
        if (end == std::string::npos) {
            if (lineNumber == 1) throw Error(filename + ": not a PLY file (it does not start with 'ply')");
            throw Error(filename + ": bad PLY header: no 'end_header' line");
        }
        const std::vector<std::string_view> words = splitWords(std::string_view(data).substr(pos, end - pos));
        pos = end + 1;
        const std::string where = filename + ": bad PLY header at line " + std::to_string(lineNumber) + ": ";
        if (lineNumber == 1) {
            if (words.size() != 1 || words[0] != "ply")
                throw Error(filename + ": not a PLY file (it does not start with 'ply')");
            continue;
        }
        if (words.empty() || words[0] == "comment" || words[0] == "obj_info") continue;
        const std::string_view keyword = words[0];
        if (keyword == "end_header") {
            if (!sawFormat) throw Error(filename + ": bad PLY header: no 'format' line");
            header.dataOffset = pos;
            header.lineCount = lineNumber;
            return header;
        }
        if (keyword == "format") {
            std::string format;
            for (size_t i = 1; i < words.size(); ++i) format += (i > 1 ? " " : "") + std::string(words[i]);
            if (format == "ascii 1.0")
                header.format = Format::Ascii;
            else if (format == "binary_little_endian 1.0")
                header.format = Format::BinaryLittleEndian;
            else if (format == "binary_big_endian 1.0")
                header.format = Format::BinaryBigEndian;
            else
                throw Error(filename + ": unsupported PLY format '" + format + "'");
            sawFormat = true;
        } else if (keyword == "element") {
            if (words.size() != 3) throw Error(where + "expected 'element NAME COUNT'");
            Element element;
            element.name = words[1];
            const auto [last, ec] = std::from_chars(words[2].data(), words[2].data() + words[2].size(), element.count);
            if (ec != std::errc() || last != words[2].data() + words[2].size())
                throw Error(where + "bad element count '" + std::string(words[2]) + "'");
            header.elements.push_back(std::move(element));
        } else if (keyword == "property") {
            if (header.elements.empty()) throw Error(where + "property before any element");
            Property property;
            const bool isList = words.size() >= 2 && words[1] == "list";
            if (words.size() != (isList ? 5u : 3u))
                throw Error(where + (isList ? "expected 'property list COUNT_TYPE TYPE NAME'"
                                            : "expected 'property TYPE NAME'"));
            for (size_t i = 1 + isList; i < words.size() - 1; ++i)
                if (!parseScalar(words[i]))
                    throw Error(where + "unknown property type '" + std::string(words[i]) + "'");
            if (isList) {
                property.listCount = parseScalar(words[2]);
                if (!isInteger(*property.listCount))
                    throw Error(where + "list count type '" + std::string(words[2]) + "' is not an integer type");
            }
            property.type = *parseScalar(words[words.size() - 2]);
            property.name = words.back();
            header.elements.back().properties.push_back(std::move(property));
        } else {
            throw Error(where + "unknown keyword '" + std::string(keyword) + "'");
        }
    }
}

// Reads the body one scalar at a time, in either encoding. Every read names its place (element, item,
// property) so that truncation and garbage are reported precisely.
class BodyReader {
  public:
    BodyReader(const std::string &data, const Header &header, const std::string &filename)
        : data_(data), pos_(header.dataOffset), format_(header.format), line_(header.lineCount + 1),
          filename_(filename) {}

    void beginItem(const Element &element, uint64_t item) {
        element_ = &element;
        item_ = item;
    }

    double read(Scalar type, const std::string &property) {
        return format_ == Format::Ascii ? readAscii(type, property) : readBinary(type);
    }

    // Skips `count` items of an element whose properties are all fixed-size scalars (binary only).
    bool trySkipFixedSize(const Element &element) {
        if (format_ == Format::Ascii) return false;
        size_t itemSize = 0;
        for (const Property &p : element.properties) {
            if (p.listCount) return false;
            itemSize += sizeOf(p.type);
        }
        const size_t remaining = data_.size() - pos_;
        if (itemSize > 0 && element.count > remaining / itemSize) {
            beginItem(element, remaining / itemSize);
            truncated();
        }
        pos_ += element.count * itemSize;
        return true;
    }

    // Used to bound reservations: a corrupt count must not allocate more than the file could hold.
    [[nodiscard]] size_t remainingBytes() const { return data_.size() - pos_; }

  private:
    [[noreturn]] void truncated() const {
        throw Error(filename_ + ": truncated in element '" + element_->name + "' at item " + std::to_string(item_) +
                    " of " + std::to_string(element_->count));
    }

    double readBinary(Scalar type) {
        const size_t size = sizeOf(type);
        if (data_.size() - pos_ < size) truncated();
        std::array<unsigned char, 8> bytes{};
        std::memcpy(bytes.data(), data_.data() + pos_, size);
        pos_ += size;
        const bool fileLittle = format_ == Format::BinaryLittleEndian;
        if (fileLittle != (std::endian::native == std::endian::little))
            std::reverse(bytes.begin(), bytes.begin() + size);
        auto as = [&bytes]<class T>(T) {
            T value;
            std::memcpy(&value, bytes.data(), sizeof(T));
            return double(value);
        };
        switch (type) {
        case Scalar::Int8:
            return as(int8_t());
        case Scalar::UInt8:
            return as(uint8_t());
        case Scalar::Int16:
            return as(int16_t());
        case Scalar::UInt16:
            return as(uint16_t());
        case Scalar::Int32:
            return as(int32_t());
        case Scalar::UInt32:
            return as(uint32_t());
        case Scalar::Float32:
            return as(float());
        case Scalar::Float64:
            return as(double());
        }
        return 0;
    }

    double readAscii(Scalar type, const std::string &property) {
        while (pos_ < data_.size() && std::isspace(static_cast<unsigned char>(data_[pos_])))
            if (data_[pos_++] == '\n') ++line_;
        if (pos_ == data_.size()) truncated();
        const size_t begin = pos_;
        while (pos_ < data_.size() && !std::isspace(static_cast<unsigned char>(data_[pos_]))) ++pos_;
        const char *first = data_.data() + begin;
        const char *last = data_.data() + pos_;
        double value = 0;
        bool ok = false;
        if (isInteger(type)) {
            int64_t integer = 0;
            const auto [end, ec] = std::from_chars(first, last, integer);
            const double lo = type == Scalar::Int8    ? -128.0
                              : type == Scalar::Int16 ? -32768.0
                              : type == Scalar::Int32 ? -2147483648.0
                                                      : 0.0;
            const double hi = double((uint64_t(1) << (8 * sizeOf(type) - (lo < 0 ? 1 : 0))) - 1);
            value = double(integer);
            ok = ec == std::errc() && end == last && value >= lo && value <= hi;
        } else {
            const auto [end, ec] = std::from_chars(first, last, value);
            ok = ec == std::errc() && end == last;
        }
        if (!ok)
            throw Error(filename_ + ":" + std::to_string(line_) + ": bad value '" + std::string(first, last) +
                        "' for property '" + property + "' of element '" + element_->name + "' (item " +
                        std::to_string(item_) + " of " + std::to_string(element_->count) + ")");
        return value;
    }

    const std::string &data_;
    size_t pos_;
    Format format_;
    size_t line_;
    const std::string &filename_;
    const Element *element_ = nullptr;
    uint64_t item_ = 0;
};

// Where each vertex property goes: position 0-2, normal 3-5, uv 6-7.
int vertexSlot(const std::string &name) {
    static const std::array<std::pair<const char *, int>, 12> slots{{{"x", 0},
                                                                     {"y", 1},
                                                                     {"z", 2},
                                                                     {"nx", 3},
                                                                     {"ny", 4},
                                                                     {"nz", 5},
                                                                     {"u", 6},
                                                                     {"v", 7},
                                                                     {"s", 6},
                                                                     {"t", 7},
                                                                     {"texture_u", 6},
                                                                     {"texture_v", 7}}};
    for (const auto &[slotName, slot] : slots)
        if (name == slotName) return slot;
    return -1;
}

} // namespace

TriangleMesh loadPly(const std::string &filename, MeshLoadReport &report) {
    const std::string data = readWholeFile(filename);
    const Header header = parseHeader(data, filename);

    const auto vertexElement = std::find_if(header.elements.begin(), header.elements.end(),
                                            [](const Element &e) { return e.name == "vertex"; });
    if (vertexElement == header.elements.end()) throw Error(filename + ": PLY file has no 'vertex' element");
    std::array<bool, 8> present{};
    for (const Property &p : vertexElement->properties)
        if (const int slot = vertexSlot(p.name); slot >= 0 && !p.listCount) present[slot] = true;
    for (int axis = 0; axis < 3; ++axis)
        if (!present[axis])
            throw Error(filename + ": element 'vertex' has no property '" + std::string(1, "xyz"[axis]) + "'");
    const bool hasNormals = present[3] && present[4] && present[5];
    const bool hasUvs = present[6] && present[7];
    const uint64_t vertexCount = vertexElement->count;
    if (vertexCount > 0xFFFFFFFFull)
        throw Error(filename + ": " + std::to_string(vertexCount) + " vertices, more than 32-bit indices can address");

    TriangleMesh mesh;
    BodyReader body(data, header, filename);
    for (const Element &element : header.elements) {
        const bool isVertex = &element == &*vertexElement;
        const bool isFace = element.name == "face";
        // Items without properties are nothing in the body, binary or ASCII, whatever their count says: a
        // count of 10^11 must not be walked item by item (a fuzz finding: an ASCII file hung here).
        if (element.properties.empty()) continue;
        if (!isVertex && !isFace && body.trySkipFixedSize(element)) continue;

        const auto indexList =
            std::find_if(element.properties.begin(), element.properties.end(), [](const Property &p) {
                return p.listCount && (p.name == "vertex_indices" || p.name == "vertex_index");
            });
        if (isFace && indexList == element.properties.end())
            throw Error(filename + ": element 'face' has no list property 'vertex_indices'");
        // Each item takes at least one byte (binary) or two characters (ASCII): never reserve beyond that.
        const size_t plausible = std::min<uint64_t>(element.count, body.remainingBytes() + 1);
        if (isVertex) {
            mesh.positions.reserve(plausible);
            if (hasNormals) mesh.normals.reserve(plausible);
            if (hasUvs) mesh.uvs.reserve(plausible);
        }

        std::vector<uint32_t> polygon;
        for (uint64_t item = 0; item < element.count; ++item) {
            body.beginItem(element, item);
            std::array<double, 8> slotValue{};
            for (auto property = element.properties.begin(); property != element.properties.end(); ++property) {
                if (!property->listCount) {
                    const double value = body.read(property->type, property->name);
                    if (isVertex)
                        if (const int slot = vertexSlot(property->name); slot >= 0) slotValue[slot] = value;
                    continue;
                }
                const double count = body.read(*property->listCount, property->name);
                if (count < 0)
                    throw Error(filename + ": negative list length in element '" + element.name + "' at item " +
                                std::to_string(item) + " of " + std::to_string(element.count));
                const bool isPolygon = isFace && property == indexList;
                if (isPolygon && count < 3)
                    throw Error(filename + ": face " + std::to_string(item) + " has " + std::to_string(int64_t(count)) +
                                " vertices; a face needs at least 3");
                polygon.clear();
                for (uint64_t k = 0; k < uint64_t(count); ++k) {
                    const double value = body.read(property->type, property->name);
                    if (!isPolygon) continue;
                    if (value != std::floor(value) || value < 0 || value >= double(vertexCount)) {
                        std::ostringstream index;
                        index << value;
                        throw Error(filename + ": face " + std::to_string(item) + " refers to vertex " + index.str() +
                                    " but the file has " + std::to_string(vertexCount) + " vertices");
                    }
                    polygon.push_back(uint32_t(value));
                }
                // Fan triangulation, as Mitsuba does for quads (and correct for any convex polygon).
                for (size_t k = 2; k < polygon.size(); ++k)
                    mesh.triangles.push_back({polygon[0], polygon[k - 1], polygon[k]});
            }
            if (isVertex) {
                mesh.positions.emplace_back(float(slotValue[0]), float(slotValue[1]), float(slotValue[2]));
                if (hasNormals)
                    mesh.normals.emplace_back(float(slotValue[3]), float(slotValue[4]), float(slotValue[5]));
                if (hasUvs) mesh.uvs.emplace_back(float(slotValue[6]), float(slotValue[7]));
            }
        }
    }

    validateMesh(mesh, filename, report);
    return mesh;
}

} // namespace lt
