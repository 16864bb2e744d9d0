// loadSerialized: Mitsuba 0.5's `.serialized` meshes. Layout as documented by the `serialized` shape
// plugin (Mitsuba 0.5 documentation, section "serialized"; src/shapes/serialized.cpp and
// TriMesh::loadCompressed in src/librender/trimesh.cpp), all little-endian:
//
//   per mesh:  u16 format id 0x041C, u16 version (3 or 4), then one zlib stream holding
//              u32 flags, [version 4: UTF-8 name, 0-terminated], u64 vertex count, u64 triangle count,
//              positions (3 reals), [normals (3 reals)], [texcoords (2 reals)], [colors (3 reals)],
//              indices (3 x u32 per triangle; u64 only when the vertex count exceeds 0xFFFFFFFF)
//   at the end: one offset per mesh (u64 in version 4, u32 in version 3), then the u32 mesh count.
//
// Reals are float unless the flags say double. Only the selected mesh is decompressed.
#include <zlib.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <cstdio>
#include <fstream>
#include <system_error>

#include "util/error.h"
#include "util/memory_budget.h"
#include "scene/mesh.h"

namespace lt {
namespace {

constexpr uint16_t kFormatId = 0x041C;
constexpr uint16_t kFormatIdOld = 0x1C04; // files of Mitsuba < 0.4, which must be re-exported
constexpr uint32_t kHasNormals = 0x0001, kHasTexcoords = 0x0002, kHasColors = 0x0008, kFaceNormals = 0x0010,
                   kDoublePrecision = 0x2000;
// zlib cannot expand data by more than about 1032:1 (zlib FAQ, "maximum compression ratio"): a vertex
// or triangle count that would need more decompressed bytes than that is corrupt, and we say so before
// allocating for it.
constexpr uint64_t kMaxInflateRatio = 1032;

template <class T> T fromLittleEndian(const unsigned char *bytes) {
    T value = 0;
    for (size_t i = 0; i < sizeof(T); ++i) value |= T(bytes[i]) << (8 * i);
    return value;
}

class SerializedFile {
  public:
    explicit SerializedFile(const std::string &filename) : filename_(filename), in_(filename, std::ios::binary) {
        if (!in_) throw Error(filename + ": cannot open file (" + std::generic_category().message(errno) + ")");
        in_.seekg(0, std::ios::end);
        size_ = uint64_t(in_.tellg());
    }

    [[nodiscard]] uint64_t size() const { return size_; }

    void readAt(uint64_t offset, void *dst, size_t n, const char *what) {
        if (offset > size_ || size_ - offset < n)
            throw Error(filename_ + ": truncated (the file ends inside " + std::string(what) + ")");
        in_.seekg(std::streamoff(offset));
        in_.read(static_cast<char *>(dst), std::streamsize(n));
        if (!in_) throw Error(filename_ + ": cannot read file");
    }

    // Reads up to n bytes at the current position; returns how many were read.
    size_t readSome(void *dst, size_t n) {
        in_.read(static_cast<char *>(dst), std::streamsize(n));
        const size_t got = size_t(in_.gcount());
        in_.clear(); // a short read at the end of the file is not a stream failure for us
        return got;
    }

    void seek(uint64_t offset) { in_.seekg(std::streamoff(offset)); }

  private:
    std::string filename_;
    std::ifstream in_;
    uint64_t size_ = 0;
};

// Pulls exactly the requested number of decompressed bytes out of one mesh's zlib stream.
class InflateReader {
  public:
    InflateReader(SerializedFile &file, uint64_t offset, std::string where) : file_(file), where_(std::move(where)) {
        file_.seek(offset);
        if (inflateInit(&stream_) != Z_OK) throw Error(where_ + ": cannot initialize zlib");
    }
    ~InflateReader() { inflateEnd(&stream_); }
    InflateReader(const InflateReader &) = delete;
    InflateReader &operator=(const InflateReader &) = delete;

    void read(void *dst, size_t n) {
        stream_.next_out = static_cast<Bytef *>(dst);
        while (n > 0) {
            if (stream_.avail_in == 0) {
                stream_.avail_in = uInt(file_.readSome(input_.data(), input_.size()));
                stream_.next_in = input_.data();
                if (stream_.avail_in == 0)
                    throw Error(where_ + ": truncated (the file ends inside the compressed data)");
            }
            const uInt chunk = uInt(std::min<size_t>(n, 1u << 30));
            stream_.avail_out = chunk;
            const int status = inflate(&stream_, Z_NO_FLUSH);
            const size_t produced = chunk - stream_.avail_out;
            n -= produced;
            if (status == Z_STREAM_END && n > 0)
                throw Error(where_ + ": truncated (the compressed data ends before the mesh it announces)");
            if (status != Z_OK && status != Z_STREAM_END && status != Z_BUF_ERROR)
                throw Error(where_ + ": corrupt compressed data (zlib: " +
                            (stream_.msg ? std::string(stream_.msg) : "error " + std::to_string(status)) + ")");
        }
    }

    template <class T> T read() {
        unsigned char bytes[sizeof(T)];
        read(bytes, sizeof(T));
        return fromLittleEndian<T>(bytes);
    }

    // Positions, normals, uvs: `count` tuples of `arity` reals, stored as float or double.
    std::vector<float> readReals(uint64_t count, size_t arity, bool doublePrecision) {
        std::vector<float> values(count * arity);
        if (!doublePrecision) {
            static_assert(std::endian::native == std::endian::little, "serialized reals are little-endian");
            read(values.data(), values.size() * sizeof(float));
            return values;
        }
        std::vector<double> doubles(values.size());
        read(doubles.data(), doubles.size() * sizeof(double));
        for (size_t i = 0; i < values.size(); ++i) values[i] = float(doubles[i]);
        return values;
    }

  private:
    SerializedFile &file_;
    std::string where_;
    z_stream stream_{};
    std::array<Bytef, 1 << 16> input_{};
};

uint16_t readVersion(SerializedFile &file, uint64_t offset, const std::string &where) {
    unsigned char header[4];
    file.readAt(offset, header, 4, "a mesh header");
    const uint16_t id = fromLittleEndian<uint16_t>(header);
    const uint16_t version = fromLittleEndian<uint16_t>(header + 2);
    if (id == kFormatIdOld)
        throw Error(where + ": written by Mitsuba older than 0.4 (format id 0x1C04); re-export the mesh");
    if (id != kFormatId) {
        char hex[8];
        std::snprintf(hex, sizeof hex, "0x%04X", id);
        throw Error(where + ": not a Mitsuba serialized mesh (format id " + hex + ", expected 0x041C)");
    }
    if (version != 3 && version != 4)
        throw Error(where + ": unsupported serialized version " + std::to_string(version) + " (expected 3 or 4)");
    return version;
}

// The offset dictionary at the end of the file. As in Mitsuba (TriMesh::readOffsetDictionary), a file
// whose dictionary is implausible is taken to hold a single mesh at offset 0 (files of early exporters
// have none). Mitsuba's plausibility test compares the file size with the *uncompressed* size of the
// smallest mesh, which misjudges files of a few tiny meshes; we instead require a dictionary that fits
// after one header and one minimal zlib stream per mesh, starts at 0 and ascends.
std::vector<uint64_t> readOffsets(SerializedFile &file, uint16_t version) {
    const uint64_t size = file.size();
    const uint64_t entrySize = version == 4 ? 8 : 4;
    const uint64_t minMeshSize = 4 + 8; // header, zlib header and checksum
    unsigned char countBytes[4];
    file.readAt(size - 4, countBytes, 4, "the mesh count");
    const uint64_t count = fromLittleEndian<uint32_t>(countBytes);
    if (count == 0 || count > (size - 4) / (minMeshSize + entrySize)) return {0};

    const uint64_t dictionaryStart = size - 4 - count * entrySize;
    std::vector<unsigned char> table(count * entrySize);
    file.readAt(dictionaryStart, table.data(), table.size(), "the offset dictionary");
    std::vector<uint64_t> offsets(count);
    for (size_t i = 0; i < count; ++i) {
        offsets[i] =
            entrySize == 8 ? fromLittleEndian<uint64_t>(&table[8 * i]) : fromLittleEndian<uint32_t>(&table[4 * i]);
        const bool ascending = i == 0 ? offsets[0] == 0 : offsets[i] >= offsets[i - 1] + minMeshSize;
        if (!ascending || offsets[i] + minMeshSize > dictionaryStart) return {0};
    }
    return offsets;
}

} // namespace

TriangleMesh loadSerialized(const std::string &filename, int shapeIndex, MeshLoadReport &report) {
    SerializedFile file(filename);
    if (file.size() < 8) throw Error(filename + ": truncated (" + std::to_string(file.size()) + " bytes)");
    const uint16_t version = readVersion(file, 0, filename);
    const std::vector<uint64_t> offsets = readOffsets(file, version);
    if (shapeIndex < 0 || size_t(shapeIndex) >= offsets.size())
        throw Error(filename + ": shapeIndex " + std::to_string(shapeIndex) + " out of range, the file holds " +
                    std::to_string(offsets.size()) + (offsets.size() == 1 ? " mesh" : " meshes"));

    const uint64_t offset = offsets[size_t(shapeIndex)];
    const std::string where = filename + ": mesh " + std::to_string(shapeIndex);
    // The dictionary layout comes from the first header (as in Mitsuba); a mesh of another version
    // would be read with the wrong name field.
    if (const uint16_t meshVersion = readVersion(file, offset, where); meshVersion != version)
        throw Error(where + " has version " + std::to_string(meshVersion) + " but the file's first mesh has version " +
                    std::to_string(version));

    InflateReader z(file, offset + 4, where);
    const uint32_t flags = z.read<uint32_t>();
    if (version == 4) // the shape name: read and dropped (the scene names shapes itself)
        for (size_t length = 0; z.read<uint8_t>() != 0; ++length)
            if (length > 65536) throw Error(where + ": corrupt data (the shape name is not terminated)");
    const uint64_t vertexCount = z.read<uint64_t>();
    const uint64_t triangleCount = z.read<uint64_t>();

    const bool doublePrecision = flags & kDoublePrecision;
    const uint64_t realSize = doublePrecision ? 8 : 4;
    const uint64_t realsPerVertex =
        3 + ((flags & kHasNormals) ? 3 : 0) + ((flags & kHasTexcoords) ? 2 : 0) + ((flags & kHasColors) ? 3 : 0);
    const uint64_t compressedBytes = file.size() - offset;
    const uint64_t maxBytes = compressedBytes * kMaxInflateRatio;
    if (vertexCount > maxBytes / (realsPerVertex * realSize) || triangleCount > maxBytes / 12 ||
        vertexCount * realsPerVertex * realSize + triangleCount * 12 > maxBytes)
        throw Error(where + ": corrupt data (" + std::to_string(vertexCount) + " vertices and " +
                    std::to_string(triangleCount) + " triangles cannot fit in " + std::to_string(compressedBytes) +
                    " compressed bytes)");
    // Mitsuba switches to u64 indices beyond 0xFFFFFFFF vertices; our meshes index with 32 bits.
    if (vertexCount > 0xFFFFFFFFull)
        throw Error(where + ": " + std::to_string(vertexCount) + " vertices, more than 32-bit indices can address");
    // Within the ratio a large file can still declare more than memory holds: the reals as read and as
    // kept (floats), the indices, and the scene's own copy of the mesh (the acceleration structure).
    requireMemory(
        2 * (double(vertexCount) * double(realsPerVertex) * double(realSize + 4) + double(triangleCount) * 12),
        where + ": a mesh of " + std::to_string(vertexCount) + " vertices and " + std::to_string(triangleCount) +
            " triangles");

    TriangleMesh mesh;
    const std::vector<float> positions = z.readReals(vertexCount, 3, doublePrecision);
    for (size_t i = 0; i < vertexCount; ++i)
        mesh.positions.emplace_back(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]);
    if (flags & kHasNormals) {
        const std::vector<float> normals = z.readReals(vertexCount, 3, doublePrecision);
        // With the face-normals flag Mitsuba ignores vertex normals when shading; dropping them does the same.
        if (!(flags & kFaceNormals))
            for (size_t i = 0; i < vertexCount; ++i)
                mesh.normals.emplace_back(normals[3 * i], normals[3 * i + 1], normals[3 * i + 2]);
    }
    if (flags & kHasTexcoords) {
        const std::vector<float> uvs = z.readReals(vertexCount, 2, doublePrecision);
        for (size_t i = 0; i < vertexCount; ++i) mesh.uvs.emplace_back(uvs[2 * i], uvs[2 * i + 1]);
    }
    if (flags & kHasColors) z.readReals(vertexCount, 3, doublePrecision); // vertex colors: not used by lt
    std::vector<unsigned char> indices(triangleCount * 12);
    z.read(indices.data(), indices.size());
    mesh.triangles.resize(triangleCount);
    for (size_t i = 0; i < triangleCount; ++i)
        for (size_t k = 0; k < 3; ++k) mesh.triangles[i][k] = fromLittleEndian<uint32_t>(&indices[12 * i + 4 * k]);

    validateMesh(mesh, filename, report);
    return mesh;
}

} // namespace lt
