// loadObj: Wavefront OBJ through tinyobjloader (a package, not a hand-written parser), with the
// checks tinyobjloader leaves out, then the shared validateMesh step.
//
// Conventions follow Mitsuba 0.5's `obj` shape plugin (src/shapes/obj.cpp): all groups and objects of a
// file form one mesh, materials (.mtl) are ignored, polygons are fan-triangulated, and texture
// coordinates are flipped vertically (its `flipTexCoords` parameter, default true), so that uv (0,0)
// addresses the first row of a bitmap texture as in Mitsuba's MIP map lookups (see texture.cpp).
#include <tiny_obj_loader.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string_view>
#include <system_error>
#include <unordered_map>

#include "util/error.h"
#include "scene/mesh.h"

namespace lt {
namespace {

std::string readWholeFile(const std::string &filename) {
    std::ifstream in(filename, std::ios::binary);
    if (!in) throw Error(filename + ": cannot open file (" + std::generic_category().message(errno) + ")");
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) throw Error(filename + ": cannot read file");
    return text.str();
}

// tinyobjloader turns an unparseable coordinate into 0 and "1e999" into inf without a word. Scanning the
// `v`, `vn` and `vt` lines once ourselves costs little and lets us name the line and the bad token.
void checkNumbers(const std::string &text, const std::string &filename) {
    size_t lineNumber = 0;
    size_t lineStart = 0;
    while (lineStart < text.size()) {
        ++lineNumber;
        size_t lineEnd = text.find('\n', lineStart);
        if (lineEnd == std::string::npos) lineEnd = text.size();
        std::string_view line(text.data() + lineStart, lineEnd - lineStart);
        lineStart = lineEnd + 1;
        if (const size_t comment = line.find('#'); comment != std::string_view::npos) line = line.substr(0, comment);

        auto nextToken = [&line]() {
            const size_t begin = line.find_first_not_of(" \t\r");
            if (begin == std::string_view::npos) return std::string_view();
            const size_t end = std::min(line.find_first_of(" \t\r", begin), line.size());
            const std::string_view token = line.substr(begin, end - begin);
            line = line.substr(end);
            return token;
        };
        const std::string_view keyword = nextToken();
        size_t required = 0;
        if (keyword == "v" || keyword == "vn")
            required = 3;
        else if (keyword == "vt")
            required = 1;
        else
            continue;

        const std::string where = filename + ":" + std::to_string(lineNumber) + ": ";
        size_t count = 0;
        for (std::string_view token = nextToken(); !token.empty(); token = nextToken(), ++count) {
            double value = 0;
            const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
            if (ec == std::errc::result_out_of_range)
                throw Error(where + "number '" + std::string(token) + "' is out of range");
            if (ec != std::errc() || end != token.data() + token.size())
                throw Error(where + "bad number '" + std::string(token) + "'");
            if (!std::isfinite(value)) throw Error(where + "non-finite number '" + std::string(token) + "'");
        }
        if (count < required)
            throw Error(where + "'" + std::string(keyword) + "' needs " + std::to_string(required) +
                        " numbers, found " + std::to_string(count));
    }
}

// tinyobjloader's messages end in newlines and may span lines; ours are exactly one line.
std::string oneLine(std::string message) {
    while (!message.empty() && (message.back() == '\n' || message.back() == '\r')) message.pop_back();
    for (char &c : message)
        if (c == '\n' || c == '\r') c = ' ';
    return message;
}

struct CornerKey {
    int v, vn, vt;
    bool operator==(const CornerKey &) const = default;
};

struct CornerKeyHash {
    size_t operator()(const CornerKey &k) const {
        const uint64_t a = uint64_t(uint32_t(k.v)) | (uint64_t(uint32_t(k.vn)) << 32);
        return std::hash<uint64_t>()(a) ^ (std::hash<int>()(k.vt) * 0x9e3779b97f4a7c15ull);
    }
};

// OBJ indices count from 1; tinyobjloader has made them 0-based (and resolved negative, relative ones).
void checkIndex(int index, size_t count, const char *what, const char *whats, size_t face,
                const std::string &filename) {
    if (index >= 0 && size_t(index) < count) return;
    const std::string prefix = filename + ": face " + std::to_string(face + 1) + " refers to ";
    if (index < 0) throw Error(prefix + "a " + what + " before the first one (a relative index reaching too far back)");
    throw Error(prefix + what + " " + std::to_string(index + 1) + " but the file has " + std::to_string(count) + " " +
                whats);
}

} // namespace

TriangleMesh loadObj(const std::string &filename, MeshLoadReport &report) {
    const std::string text = readWholeFile(filename);
    checkNumbers(text, filename);

    tinyobj::ObjReaderConfig config;
    config.triangulate = false; // we fan-triangulate ourselves, so face numbers in messages are the file's
    config.vertex_color = false;
    tinyobj::ObjReader reader;
    // ParseFromString ignores `mtllib`: a missing .mtl is no error, as in Mitsuba, which ignores materials.
    if (!reader.ParseFromString(text, "", config)) throw Error(filename + ": " + oneLine(reader.Error()));

    const tinyobj::attrib_t &attrib = reader.GetAttrib();
    const size_t positionCount = attrib.vertices.size() / 3;
    const size_t normalCount = attrib.normals.size() / 3;
    const size_t uvCount = attrib.texcoords.size() / 2;

    // Normals and uvs are kept only when every face corner has one: the mesh stores them per vertex,
    // all or nothing, and a partly textured mesh is far more likely an exporter slip than intent.
    bool allNormals = true, allUvs = true;
    size_t face = 0;
    for (const tinyobj::shape_t &shape : reader.GetShapes()) {
        size_t corner = 0;
        for (const unsigned char cornerCount : shape.mesh.num_face_vertices) {
            for (size_t k = 0; k < cornerCount; ++k) {
                const tinyobj::index_t &index = shape.mesh.indices[corner + k];
                checkIndex(index.vertex_index, positionCount, "vertex", "vertices", face, filename);
                if (index.normal_index == -1)
                    allNormals = false;
                else
                    checkIndex(index.normal_index, normalCount, "normal", "normals", face, filename);
                if (index.texcoord_index == -1)
                    allUvs = false;
                else
                    checkIndex(index.texcoord_index, uvCount, "texture coordinate", "texture coordinates", face,
                               filename);
            }
            corner += cornerCount;
            ++face;
        }
    }

    // One mesh vertex per distinct (v, vn, vt) triple: corners that share all three stay shared, so
    // interpolated normals and uvs are continuous where the file says they are.
    TriangleMesh mesh;
    std::unordered_map<CornerKey, uint32_t, CornerKeyHash> vertexOf;
    auto meshVertex = [&](const tinyobj::index_t &index) {
        const CornerKey key{index.vertex_index, allNormals ? index.normal_index : -1,
                            allUvs ? index.texcoord_index : -1};
        const auto [it, inserted] = vertexOf.try_emplace(key, uint32_t(mesh.positions.size()));
        if (inserted) {
            const float *p = &attrib.vertices[3 * size_t(key.v)];
            mesh.positions.emplace_back(p[0], p[1], p[2]);
            if (allNormals) {
                const float *n = &attrib.normals[3 * size_t(key.vn)];
                mesh.normals.emplace_back(n[0], n[1], n[2]);
            }
            if (allUvs) {
                const float *t = &attrib.texcoords[2 * size_t(key.vt)];
                mesh.uvs.emplace_back(t[0], 1.0f - t[1]); // Mitsuba's flipTexCoords (see top of file)
            }
        }
        return it->second;
    };
    for (const tinyobj::shape_t &shape : reader.GetShapes()) {
        size_t corner = 0;
        for (const unsigned char cornerCount : shape.mesh.num_face_vertices) {
            if (cornerCount < 3) { // tinyobjloader already drops such faces; never read past them
                corner += cornerCount;
                continue;
            }
            const uint32_t first = meshVertex(shape.mesh.indices[corner]);
            uint32_t previous = meshVertex(shape.mesh.indices[corner + 1]);
            for (size_t k = 2; k < cornerCount; ++k) {
                const uint32_t current = meshVertex(shape.mesh.indices[corner + k]);
                mesh.triangles.push_back({first, previous, current});
                previous = current;
            }
            corner += cornerCount;
        }
    }

    validateMesh(mesh, filename, report);
    return mesh;
}

} // namespace lt
