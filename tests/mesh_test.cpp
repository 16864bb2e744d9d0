// Mesh loaders (OBJ, PLY, Mitsuba serialized) and validateMesh: values read back exactly, and every
// error path with its one-line message. Test files are written at run time into a temporary directory.
#include <zlib.h>

#include <bit>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include "util/error.h"
#include "test_util.h"
#include "scene/mesh.h"

namespace fs = std::filesystem;
using namespace lt;

namespace {

using test::TempDir;

// ------------------------------------------------------------------------------------------- OBJ

// Two quads sharing the edge 2-3, written as two groups, with a material library that does not exist.
const char *kTwoQuadsObj = R"(# two unit quads side by side
mtllib missing.mtl
o first
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 2 0 0
v 2 1 0
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vn 0 0 1
usemtl nothing
f 1/1/1 2/2/1 3/3/1 4/4/1
g second
f 2/2/1 5/1/1 6/4/1 3/3/1
)";

} // namespace

TEST_CASE("OBJ: quads are fan-triangulated, groups merged, shared (v, vt, vn) triples stay shared", "[mesh]") {
    TempDir dir;
    MeshLoadReport report;
    const TriangleMesh mesh = loadObj(dir.write("quads.obj", kTwoQuadsObj), report);
    // Corners 2/2/1 and 3/3/1 appear in both quads: 8 corners, 6 distinct triples.
    REQUIRE(mesh.positions.size() == 6);
    REQUIRE(mesh.normals.size() == 6);
    REQUIRE(mesh.uvs.size() == 6);
    REQUIRE(mesh.triangles.size() == 4);
    CHECK(report.degenerateTrianglesRemoved == 0);
    // Vertices are numbered in order of first use; fan of quad (a b c d) is (a b c), (a c d).
    CHECK(mesh.triangles[0] == std::array<uint32_t, 3>{0, 1, 2});
    CHECK(mesh.triangles[1] == std::array<uint32_t, 3>{0, 2, 3});
    CHECK(mesh.triangles[2] == std::array<uint32_t, 3>{1, 4, 5});
    CHECK(mesh.triangles[3] == std::array<uint32_t, 3>{1, 5, 2});
    CHECK(mesh.positions[4] == Vec3f(2, 0, 0));
    CHECK(mesh.normals[3] == Vec3f(0, 0, 1));
    // Mitsuba's obj plugin flips v (flipTexCoords = true): vt (1, 1) becomes uv (1, 0).
    CHECK(mesh.uvs[2] == Vec2f(1, 0));
    CHECK(mesh.uvs[0] == Vec2f(0, 1));
}

TEST_CASE("OBJ: the same position with different texture coordinates becomes two vertices", "[mesh]") {
    TempDir dir;
    MeshLoadReport report;
    const TriangleMesh mesh = loadObj(dir.write("seam.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
                                                            "vt 0 0\nvt 1 0\nvt 0 1\nvt 0.5 0.5\n"
                                                            "f 1/1 2/2 3/3\nf 2/4 4/2 3/3\n"),
                                      report);
    CHECK(mesh.positions.size() == 5); // vertex 2 appears with vt 2 and vt 4
    CHECK(mesh.normals.empty());
    CHECK(mesh.triangles.size() == 2);
}

TEST_CASE("OBJ: a pentagon becomes a fan of three triangles; faces without normals drop them all", "[mesh]") {
    TempDir dir;
    MeshLoadReport report;
    const TriangleMesh mesh =
        loadObj(dir.write("pentagon.obj", "v 0 0 0\nv 2 0 0\nv 3 1 0\nv 1 2 0\nv -1 1 0\nvn 0 0 1\n"
                                          "f 1//1 2//1 3//1 4//1 5\n"),
                report);
    CHECK(mesh.triangles.size() == 3);
    CHECK(mesh.triangles[2] == std::array<uint32_t, 3>{0, 3, 4});
    CHECK(mesh.normals.empty());
}

TEST_CASE("OBJ: error messages", "[mesh]") {
    TempDir dir;
    MeshLoadReport report;
    const std::string missing = (dir.path / "nope.obj").string();
    CHECK(test::errorOf([&] { loadObj(missing, report); }) == missing + ": cannot open file (No such file or directory)");

    const std::string bad = dir.write("bad.obj", "v 0 0 0\nv 1 abc 0\nv 1 1 0\nf 1 2 3\n");
    CHECK(test::errorOf([&] { loadObj(bad, report); }) == bad + ":2: bad number 'abc'");

    const std::string nan = dir.write("nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n");
    CHECK(test::errorOf([&] { loadObj(nan, report); }) == nan + ":3: non-finite number 'nan'");

    const std::string huge = dir.write("huge.obj", "v 0 0 0\nv 1 0 1e999\nv 1 1 0\nf 1 2 3\n");
    CHECK(test::errorOf([&] { loadObj(huge, report); }) == huge + ":2: number '1e999' is out of range");

    const std::string shortV = dir.write("short.obj", "v 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n");
    CHECK(test::errorOf([&] { loadObj(shortV, report); }) == shortV + ":1: 'v' needs 3 numbers, found 2");

    const std::string range = dir.write("range.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\nf 1 2 9\n");
    CHECK(test::errorOf([&] { loadObj(range, report); }) ==
          range + ": face 2 refers to vertex 9 but the file has 3 vertices");

    const std::string back = dir.write("back.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf -10 1 2\n");
    CHECK(test::errorOf([&] { loadObj(back, report); }) ==
          back + ": face 1 refers to a vertex before the first one (a relative index reaching too far back)");

    const std::string normal = dir.write("normal.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nvn 0 0 1\nf 1//1 2//5 3//1\n");
    CHECK(test::errorOf([&] { loadObj(normal, report); }) ==
          normal + ": face 1 refers to normal 5 but the file has 1 normals");

    // tinyobjloader's own message, prefixed with the file name and kept on one line.
    const std::string face = dir.write("face.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 x\n");
    CHECK(test::errorOf([&] { loadObj(face, report); }) ==
          face + ": Failed parse `f' line(e.g. zero value for face index. line 4.)");
}

TEST_CASE("OBJ: degenerate triangles are removed and counted; an all-degenerate mesh is an error", "[mesh]") {
    TempDir dir;
    MeshLoadReport report;
    // Triangle 2 repeats a vertex, triangle 3 is collinear (zero area in float).
    const std::string file = dir.write("degenerate.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\n"
                                                         "f 1 2 3\nf 1 1 2\nf 1 2 4\n");
    const TriangleMesh mesh = loadObj(file, report);
    CHECK(mesh.triangles.size() == 1);
    CHECK(report.degenerateTrianglesRemoved == 2);

    const std::string flat = dir.write("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\nf 3 2 1\n");
    CHECK(test::errorOf([&] { loadObj(flat, report); }) == flat + ": no non-degenerate triangles");
    const std::string empty = dir.write("empty.obj", "# nothing here\n");
    CHECK(test::errorOf([&] { loadObj(empty, report); }) == empty + ": no non-degenerate triangles");
}

TEST_CASE("OBJ: the veach-bidir meshes load with plausible counts", "[mesh]") {
    const fs::path models = fs::path(LT_SOURCE_DIR) / "scenes/veach-bidir/models";
    REQUIRE(fs::exists(models));
    size_t files = 0;
    for (const auto &entry : fs::directory_iterator(models)) {
        if (entry.path().extension() != ".obj") continue;
        ++files;
        size_t vLines = 0, fLines = 0;
        std::ifstream in(entry.path());
        for (std::string line; std::getline(in, line);) {
            vLines += line.rfind("v ", 0) == 0;
            fLines += line.rfind("f ", 0) == 0;
        }
        MeshLoadReport report;
        INFO(entry.path().string());
        const TriangleMesh mesh = loadObj(entry.path().string(), report);
        // These files use one vt and vn per v (f i/i/i), and only triangles.
        CHECK(mesh.positions.size() == vLines);
        CHECK(mesh.normals.size() == mesh.positions.size());
        CHECK(mesh.uvs.size() == mesh.positions.size());
        CHECK(mesh.triangles.size() + report.degenerateTrianglesRemoved == fLines);
        CHECK(mesh.triangles.size() >= 10);
    }
    CHECK(files == 12);
}

// ----------------------------------------------------------------------------------- validateMesh

TEST_CASE("validateMesh: messages name the vertex or triangle", "[mesh]") {
    MeshLoadReport report;
    auto square = [] {
        TriangleMesh m;
        m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
        m.triangles = {{0, 1, 2}, {0, 2, 3}};
        return m;
    };
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();

    TriangleMesh m = square();
    m.positions[2] = {nan, 0, 1};
    CHECK(test::errorOf([&] { validateMesh(m, "models/bad.obj", report); }) ==
          "models/bad.obj: vertex 2 has a non-finite position (nan, 0, 1)");
    m = square();
    m.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, -inf, 1}};
    CHECK(test::errorOf([&] { validateMesh(m, "m.ply", report); }) == "m.ply: vertex 3 has a non-finite normal (0, -inf, 1)");
    m = square();
    m.uvs = {{0, 0}, {nan, 0}, {0, 0}, {0, 0}};
    CHECK(test::errorOf([&] { validateMesh(m, "m.ply", report); }) == "m.ply: vertex 1 has a non-finite uv (nan, 0)");
    m = square();
    m.normals = {{0, 0, 1}};
    CHECK(test::errorOf([&] { validateMesh(m, "m.ply", report); }) == "m.ply: the mesh has 4 vertices but 1 normals");
    m = square();
    m.triangles[1] = {0, 99, 3};
    CHECK(test::errorOf([&] { validateMesh(m, "models/bad.obj", report); }) ==
          "models/bad.obj: triangle 1 refers to vertex 99 but the mesh has 4 vertices");

    // A triangle whose area underflows in float is as degenerate as a collinear one.
    m = square();
    m.positions.push_back({0, 0, 1e-30f});
    m.positions.push_back({1e-30f, 0, 0});
    m.triangles.push_back({0, 4, 5});
    report = {};
    validateMesh(m, "tiny.obj", report);
    CHECK(m.triangles.size() == 2);
    CHECK(report.degenerateTrianglesRemoved == 1);
}

// ------------------------------------------------------------------------------------------- PLY

namespace {

// The same little mesh in every PLY flavour: a unit quad (fan-triangulated) and a triangle on top,
// 5 vertices with normals and uvs.
struct PlyVertex {
    float x, y, z;
    double nx, ny, nz;
    float u, v;
};
const std::vector<PlyVertex> kPlyVertices = {{0, 0, 0, 0, 0, 1, 0, 0},
                                             {1, 0, 0, 0, 0, 1, 1, 0},
                                             {1, 1, 0, 0, 0, 1, 1, 1},
                                             {0, 1, 0, 0, 0, 1, 0, 1},
                                             {0.5f, 2, 0, 0, 0.6, 0.8, 0.5f, 0.25f}};
const std::vector<std::vector<int>> kPlyFaces = {{0, 1, 2, 3}, {3, 2, 4}};

void checkPlyMesh(const TriangleMesh &mesh) {
    REQUIRE(mesh.positions.size() == 5);
    REQUIRE(mesh.normals.size() == 5);
    REQUIRE(mesh.uvs.size() == 5);
    REQUIRE(mesh.triangles.size() == 3);
    CHECK(mesh.positions[4] == Vec3f(0.5f, 2, 0));
    CHECK(mesh.normals[4] == Vec3f(0, 0.6f, 0.8f));
    CHECK(mesh.uvs[4] == Vec2f(0.5f, 0.25f)); // PLY uvs are used as stored (Mitsuba's ply plugin)
    CHECK(mesh.triangles[0] == std::array<uint32_t, 3>{0, 1, 2});
    CHECK(mesh.triangles[1] == std::array<uint32_t, 3>{0, 2, 3});
    CHECK(mesh.triangles[2] == std::array<uint32_t, 3>{3, 2, 4});
}

std::string asciiPly() {
    std::ostringstream out;
    out << "ply\r\nformat ascii 1.0\ncomment made by mesh_test\nelement vertex 5\n"
           "property float x\nproperty float y\nproperty float z\n"
           "property double nx\nproperty double ny\nproperty double nz\nproperty float s\nproperty float t\n"
           "element face 2\nproperty list uchar int vertex_indices\n"
           "element material 1\nproperty list uchar float values\nproperty uchar id\nend_header\n";
    for (const PlyVertex &v : kPlyVertices)
        out << v.x << " " << v.y << " " << v.z << " " << v.nx << " " << v.ny << " " << v.nz << " " << v.u << " " << v.v
            << "\n";
    for (const auto &f : kPlyFaces) {
        out << f.size();
        for (int i : f) out << " " << i;
        out << "\n";
    }
    out << "2 0.5 0.25 7\n";
    return out.str();
}

// Binary PLY with mixed types, an extra fixed-size element between vertices and faces (skipped by its
// size) and `vertex_index` with ushort counts and uint indices.
class BinaryPly {
  public:
    explicit BinaryPly(bool bigEndian) : big_(bigEndian) {}

    std::string header() const {
        return std::string("ply\nformat ") + (big_ ? "binary_big_endian" : "binary_little_endian") +
               " 1.0\nelement vertex 5\nproperty float32 x\nproperty float32 y\nproperty float32 z\n"
               "property uchar flags\nproperty float64 nx\nproperty float64 ny\nproperty float64 nz\n"
               "property float texture_u\nproperty float texture_v\n"
               "element edge 2\nproperty int vertex1\nproperty int16 vertex2\n"
               "element face 2\nproperty list ushort uint vertex_index\nend_header\n";
    }
    std::string body() const {
        std::string out;
        for (const PlyVertex &v : kPlyVertices) {
            put(out, v.x), put(out, v.y), put(out, v.z), put(out, uint8_t(9));
            put(out, v.nx), put(out, v.ny), put(out, v.nz), put(out, v.u), put(out, v.v);
        }
        for (int e = 0; e < 2; ++e) put(out, int32_t(e)), put(out, int16_t(e + 1));
        for (const auto &f : kPlyFaces) {
            put(out, uint16_t(f.size()));
            for (int i : f) put(out, uint32_t(i));
        }
        return out;
    }
    static constexpr size_t kVertexSize = 3 * 4 + 1 + 3 * 8 + 2 * 4;
    static constexpr size_t kEdgeSize = 4 + 2;

  private:
    template <class T> void put(std::string &out, T value) const {
        char bytes[sizeof(T)];
        std::memcpy(bytes, &value, sizeof(T));
        if (big_ == (std::endian::native == std::endian::little)) std::reverse(bytes, bytes + sizeof(T));
        out.append(bytes, sizeof(T));
    }
    bool big_;
};

} // namespace

TEST_CASE("PLY: ascii, binary little-endian and big-endian give the same mesh", "[mesh]") {
    TempDir dir;
    MeshLoadReport report;
    checkPlyMesh(loadPly(dir.write("ascii.ply", asciiPly()), report));
    const BinaryPly little(false), big(true);
    checkPlyMesh(loadPly(dir.write("little.ply", little.header() + little.body()), report));
    checkPlyMesh(loadPly(dir.write("big.ply", big.header() + big.body()), report));
    CHECK(report.degenerateTrianglesRemoved == 0);
}

TEST_CASE("PLY: an element without properties is nothing to read, whatever its count", "[mesh]") {
    // Before, an ASCII file declaring 10^11 such items walked them one by one: a hang (fuzz finding
    // tests/fuzz/corpus/ply-loader/finding-ascii-element-without-properties.ply).
    TempDir dir;
    MeshLoadReport report;
    std::string ascii = asciiPly();
    ascii.insert(ascii.find("element vertex"), "element marker 100000000000\n");
    checkPlyMesh(loadPly(dir.write("marker.ply", ascii), report));
    std::string binary = BinaryPly(false).header() + BinaryPly(false).body();
    binary.insert(binary.find("element face"), "element marker 100000000000\n");
    checkPlyMesh(loadPly(dir.write("marker_binary.ply", binary), report));
}

TEST_CASE("PLY: truncation is reported with element and item", "[mesh]") {
    TempDir dir;
    MeshLoadReport report;
    const BinaryPly ply(false);
    const std::string header = ply.header(), body = ply.body();
    auto cutAt = [&](size_t bodyBytes) {
        const std::string file = dir.write("cut.ply", header + body.substr(0, bodyBytes));
        return test::errorOf([&] { loadPly(file, report); }).substr(file.size());
    };
    const size_t vertices = 5 * BinaryPly::kVertexSize, edges = 2 * BinaryPly::kEdgeSize;
    CHECK(cutAt(0) == ": truncated in element 'vertex' at item 0 of 5");
    CHECK(cutAt(2 * BinaryPly::kVertexSize + 13) == ": truncated in element 'vertex' at item 2 of 5");
    CHECK(cutAt(vertices + BinaryPly::kEdgeSize + 3) == ": truncated in element 'edge' at item 1 of 2");
    CHECK(cutAt(vertices + edges + 1) == ": truncated in element 'face' at item 0 of 2");
    CHECK(cutAt(body.size() - 1) == ": truncated in element 'face' at item 1 of 2");

    const std::string ascii = asciiPly();
    const std::string cut = dir.write("cut_ascii.ply", ascii.substr(0, ascii.find("\n3 3 2 4")));
    CHECK(test::errorOf([&] { loadPly(cut, report); }) == cut + ": truncated in element 'face' at item 1 of 2");
}

TEST_CASE("PLY: header and value errors", "[mesh]") {
    TempDir dir;
    MeshLoadReport report;
    auto errorFor = [&](const std::string &contents) {
        const std::string file = dir.write("bad.ply", contents);
        return test::errorOf([&] { loadPly(file, report); }).substr(file.size());
    };
    const std::string missing = (dir.path / "nope.ply").string();
    CHECK(test::errorOf([&] { loadPly(missing, report); }) == missing + ": cannot open file (No such file or directory)");
    CHECK(errorFor("PLY\nformat ascii 1.0\nend_header\n") == ": not a PLY file (it does not start with 'ply')");
    CHECK(errorFor("ply\nformat binary_ppc 1.0\nend_header\n") == ": unsupported PLY format 'binary_ppc 1.0'");
    CHECK(errorFor("ply\nformat ascii 1.0\nelement vertex 3\nproperty flot x\nend_header\n") ==
          ": bad PLY header at line 4: unknown property type 'flot'");
    CHECK(errorFor("ply\nformat ascii 1.0\nelement vertex many\n") ==
          ": bad PLY header at line 3: bad element count 'many'");
    CHECK(errorFor("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n") ==
          ": bad PLY header: no 'end_header' line");
    CHECK(errorFor("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n") ==
          ": element 'vertex' has no property 'z'");

    const std::string threeVertices =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    CHECK(errorFor(threeVertices + "0 0 0\n1 abc 0\n0 1 0\n3 0 1 2\n") ==
          ":11: bad value 'abc' for property 'y' of element 'vertex' (item 1 of 3)");
    CHECK(errorFor(threeVertices + "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n") ==
          ": face 0 refers to vertex 7 but the file has 3 vertices");
    CHECK(errorFor(threeVertices + "0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n") ==
          ": face 0 refers to vertex -1 but the file has 3 vertices");
    CHECK(errorFor(threeVertices + "0 0 0\n1 0 0\n0 1 0\n2 0 1\n") ==
          ": face 0 has 2 vertices; a face needs at least 3");
    CHECK(errorFor(threeVertices + "0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n") ==
          ": vertex 1 has a non-finite position (1, nan, 0)");
    CHECK(errorFor(threeVertices + "0 0 0\n1 0 0\n2 0 0\n3 0 1 2\n") == ": no non-degenerate triangles");
    std::string signedCount = threeVertices;
    signedCount.replace(signedCount.find("list uchar"), 10, "list char");
    CHECK(errorFor(signedCount + "0 0 0\n1 0 0\n0 1 0\n-3 0 1 2\n") ==
          ": negative list length in element 'face' at item 0 of 1");
}

// ------------------------------------------------------------------------------------ serialized

namespace {

struct SerializedMeshData {
    uint32_t flags = 0;
    std::string name;
    std::vector<double> positions, normals, uvs, colors; // flattened
    std::vector<uint32_t> indices;
    std::optional<uint64_t> announcedTriangles; // to write a header that promises more than the data holds
};

template <class T> void putLE(std::string &out, T value) {
    for (size_t i = 0; i < sizeof(T); ++i) out.push_back(char((uint64_t(value) >> (8 * i)) & 0xFF));
}

// One mesh as Mitsuba 0.5 writes it (TriMesh::serialize): header, then the zlib-compressed payload.
std::string serializeMesh(uint16_t version, const SerializedMeshData &m) {
    std::string payload;
    putLE(payload, m.flags);
    if (version == 4) payload += m.name + '\0';
    putLE(payload, uint64_t(m.positions.size() / 3));
    putLE(payload, m.announcedTriangles.value_or(m.indices.size() / 3));
    const bool doubles = m.flags & 0x2000;
    for (const auto *array : {&m.positions, &m.normals, &m.uvs, &m.colors})
        for (double v : *array) {
            if (doubles)
                payload.append(reinterpret_cast<const char *>(&v), 8);
            else {
                const float f = float(v);
                payload.append(reinterpret_cast<const char *>(&f), 4);
            }
        }
    for (uint32_t i : m.indices) putLE(payload, i);

    uLongf size = compressBound(uLong(payload.size()));
    std::string compressed(size, '\0');
    REQUIRE(compress2(reinterpret_cast<Bytef *>(compressed.data()), &size,
                      reinterpret_cast<const Bytef *>(payload.data()), uLong(payload.size()),
                      Z_BEST_COMPRESSION) == Z_OK);
    compressed.resize(size);
    std::string out;
    putLE(out, uint16_t(0x041C));
    putLE(out, version);
    return out + compressed;
}

std::string serializedFile(uint16_t version, const std::vector<SerializedMeshData> &meshes) {
    std::string out;
    std::vector<uint64_t> offsets;
    for (const auto &m : meshes) {
        offsets.push_back(out.size());
        out += serializeMesh(version, m);
    }
    for (uint64_t o : offsets) version == 4 ? putLE(out, o) : putLE(out, uint32_t(o));
    putLE(out, uint32_t(meshes.size()));
    return out;
}

SerializedMeshData triangleMesh(uint32_t flags) {
    SerializedMeshData m;
    m.flags = flags;
    m.name = "triangle";
    m.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0.1};
    m.indices = {0, 1, 2};
    if (flags & 0x0001) m.normals = {0, 0, 1, 0, 0, 1, 0, 0.6, 0.8};
    if (flags & 0x0002) m.uvs = {0, 0, 1, 0, 0.25, 0.75};
    if (flags & 0x0008) m.colors = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    return m;
}

SerializedMeshData quadMesh(uint32_t flags) {
    SerializedMeshData m;
    m.flags = flags;
    m.name = "quad";
    m.positions = {0, 0, 2, 3, 0, 2, 3, 3, 2, 0, 3, 2};
    m.indices = {0, 1, 2, 0, 2, 3, 0, 0, 1}; // the last triangle is degenerate
    if (flags & 0x0001) m.normals = {0, 0, -1, 0, 0, -1, 0, 0, -1, 0, 0, -1};
    if (flags & 0x0002) m.uvs = {0, 0, 1, 0, 1, 1, 0, 1};
    return m;
}

} // namespace

TEST_CASE("serialized: version 3 and 4 files with two meshes, float and double precision", "[mesh]") {
    TempDir dir;
    for (uint16_t version : {uint16_t(3), uint16_t(4)}) {
        INFO("version " << version);
        // Version 3: float triangle with normals, double quad with uvs. Version 4 the other way round.
        const uint32_t first = version == 3 ? 0x1000 : 0x2000, second = version == 3 ? 0x2000 : 0x1000;
        const std::string file = dir.write(
            "two.serialized",
            serializedFile(version, {triangleMesh(first | 0x0001 | 0x0002 | 0x0008), quadMesh(second | 0x0002)}));
        MeshLoadReport report;
        const TriangleMesh a = loadSerialized(file, 0, report);
        REQUIRE(a.positions.size() == 3);
        REQUIRE(a.triangles.size() == 1);
        CHECK(a.positions[2] == Vec3f(0, 1, 0.1f));
        REQUIRE(a.normals.size() == 3);
        CHECK(a.normals[2] == Vec3f(0, 0.6f, 0.8f));
        REQUIRE(a.uvs.size() == 3);
        CHECK(a.uvs[2] == Vec2f(0.25f, 0.75f)); // serialized uvs are used as stored
        CHECK(report.degenerateTrianglesRemoved == 0);

        const TriangleMesh b = loadSerialized(file, 1, report);
        REQUIRE(b.positions.size() == 4);
        CHECK(b.positions[2] == Vec3f(3, 3, 2));
        CHECK(b.normals.empty());
        REQUIRE(b.uvs.size() == 4);
        CHECK(b.uvs[3] == Vec2f(0, 1));
        REQUIRE(b.triangles.size() == 2);
        CHECK(b.triangles[1] == std::array<uint32_t, 3>{0, 2, 3});
        CHECK(report.degenerateTrianglesRemoved == 1);
    }
}

TEST_CASE("serialized: the face-normals flag drops vertex normals, as Mitsuba ignores them", "[mesh]") {
    TempDir dir;
    const std::string file = dir.write("faceted.serialized", serializedFile(4, {quadMesh(0x1000 | 0x0001 | 0x0010)}));
    MeshLoadReport report;
    const TriangleMesh mesh = loadSerialized(file, 0, report);
    CHECK(mesh.normals.empty());
    CHECK(mesh.triangles.size() == 2);
}

TEST_CASE("serialized: error messages", "[mesh]") {
    TempDir dir;
    MeshLoadReport report;
    const std::string good = serializedFile(4, {triangleMesh(0x1000), quadMesh(0x2000)});
    const std::string file = dir.write("two.serialized", good);
    CHECK(test::errorOf([&] { loadSerialized(file, 5, report); }) ==
          file + ": shapeIndex 5 out of range, the file holds 2 meshes");
    CHECK(test::errorOf([&] { loadSerialized(file, -1, report); }) ==
          file + ": shapeIndex -1 out of range, the file holds 2 meshes");

    const std::string missing = (dir.path / "nope.serialized").string();
    CHECK(test::errorOf([&] { loadSerialized(missing, 0, report); }) ==
          missing + ": cannot open file (No such file or directory)");

    std::string badId = good;
    badId[0] = 0x34, badId[1] = 0x12;
    const std::string badIdFile = dir.write("id.serialized", badId);
    CHECK(test::errorOf([&] { loadSerialized(badIdFile, 0, report); }) ==
          badIdFile + ": not a Mitsuba serialized mesh (format id 0x1234, expected 0x041C)");

    std::string badVersion = good;
    badVersion[2] = 5;
    const std::string badVersionFile = dir.write("version.serialized", badVersion);
    CHECK(test::errorOf([&] { loadSerialized(badVersionFile, 0, report); }) ==
          badVersionFile + ": unsupported serialized version 5 (expected 3 or 4)");

    // The second mesh's zlib header (two bytes after its own 4-byte header) made invalid.
    const size_t second = serializeMesh(4, triangleMesh(0x1000)).size();
    std::string corrupt = good;
    corrupt[second + 4] = char(0xFF);
    const std::string corruptFile = dir.write("corrupt.serialized", corrupt);
    CHECK(test::errorOf([&] { loadSerialized(corruptFile, 1, report); }) ==
          corruptFile + ": mesh 1: corrupt compressed data (zlib: incorrect header check)");
    CHECK(loadSerialized(corruptFile, 0, report).triangles.size() == 1); // the first mesh is intact

    // Cut inside the first mesh: the dictionary is gone, so (as Mitsuba does) the file is taken to hold
    // one mesh at offset 0, whose compressed data then ends early.
    const std::string cutFile = dir.write("cut.serialized", good.substr(0, second - 6));
    CHECK(test::errorOf([&] { loadSerialized(cutFile, 0, report); }) ==
          cutFile + ": mesh 0: truncated (the file ends inside the compressed data)");

    // A well-formed zlib stream that ends before the announced data.
    SerializedMeshData shortMesh = triangleMesh(0x1000);
    shortMesh.announcedTriangles = 2;
    const std::string shortFile = dir.write("short.serialized", serializedFile(3, {shortMesh}));
    CHECK(test::errorOf([&] { loadSerialized(shortFile, 0, report); }) ==
          shortFile + ": mesh 0: truncated (the compressed data ends before the mesh it announces)");

    SerializedMeshData nanMesh = triangleMesh(0x2000);
    nanMesh.positions[4] = std::numeric_limits<double>::quiet_NaN();
    const std::string nanFile = dir.write("nan.serialized", serializedFile(4, {nanMesh}));
    CHECK(test::errorOf([&] { loadSerialized(nanFile, 0, report); }) ==
          nanFile + ": vertex 1 has a non-finite position (1, nan, 0)");
}
