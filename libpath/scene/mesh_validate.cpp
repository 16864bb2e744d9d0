// validateMesh: the one place where every mesh loader's output is checked before it reaches Embree or
// the samplers (no NaN or Inf ever reaches an output, and errors name the file).
#include <cmath>
#include <sstream>
#include <string>

#include "util/error.h"
#include "scene/mesh.h"

namespace lt {
namespace {

// Print NaN without its sign bit ("nan", never "-nan"), so messages do not depend on how the NaN was made.
std::string formatNumber(float v) {
    if (std::isnan(v)) return "nan";
    std::ostringstream out;
    out << v;
    return out.str();
}

std::string formatVec(const Vec3f &v) {
    return "(" + formatNumber(v.x) + ", " + formatNumber(v.y) + ", " + formatNumber(v.z) + ")";
}

std::string formatVec(const Vec2f &v) {
    return "(" + formatNumber(v.x) + ", " + formatNumber(v.y) + ")";
}

template <class Attribute> void checkAttribute(const std::vector<Attribute> &values, size_t vertexCount,
                                               const char *what, const std::string &filename) {
    if (!values.empty() && values.size() != vertexCount)
        throw Error(filename + ": the mesh has " + std::to_string(vertexCount) + " vertices but " +
                    std::to_string(values.size()) + " " + what + "s");
    for (size_t i = 0; i < values.size(); ++i)
        if (!isFinite(values[i]))
            throw Error(filename + ": vertex " + std::to_string(i) + " has a non-finite " + what + " " +
                        formatVec(values[i]));
}

// Zero area in float: the cross product of two edges, evaluated in float as Embree does, has a squared
// length of exactly zero (collinear or coincident corners, or an area so small that it underflows).
// Such a triangle can never be hit reliably, and its geometric normal would be 0/0.
bool hasZeroArea(const TriangleMesh &mesh, const std::array<uint32_t, 3> &t) {
    const Vec3f &p0 = mesh.positions[t[0]];
    const Vec3f n = cross(mesh.positions[t[1]] - p0, mesh.positions[t[2]] - p0);
    return lengthSquared(n) == 0.0f;
}

} // namespace

void validateMesh(TriangleMesh &mesh, const std::string &filename, MeshLoadReport &report) {
    const size_t vertexCount = mesh.positions.size();
    checkAttribute(mesh.positions, vertexCount, "position", filename);
    checkAttribute(mesh.normals, vertexCount, "normal", filename);
    checkAttribute(mesh.uvs, vertexCount, "uv", filename);

    // Out-of-range indices are errors (the file is broken); degenerate triangles are only removed and
    // counted, since exporters produce them routinely and Mitsuba renders such files without complaint.
    size_t kept = 0;
    for (size_t i = 0; i < mesh.triangles.size(); ++i) {
        const auto &t = mesh.triangles[i];
        for (uint32_t index : t)
            if (index >= vertexCount)
                throw Error(filename + ": triangle " + std::to_string(i) + " refers to vertex " +
                            std::to_string(index) + " but the mesh has " + std::to_string(vertexCount) + " vertices");
        const bool repeatedIndex = t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
        if (repeatedIndex || hasZeroArea(mesh, t)) continue;
        mesh.triangles[kept++] = t;
    }
    report.degenerateTrianglesRemoved += mesh.triangles.size() - kept;
    mesh.triangles.resize(kept);

    if (mesh.triangles.empty()) throw Error(filename + ": no non-degenerate triangles");
}

} // namespace lt
