// Triangle meshes as loaded from disk, before the scene's toWorld transform is applied.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "math/vec.h"

namespace lt {

struct TriangleMesh {
    std::vector<Vec3f> positions;
    std::vector<Vec3f> normals;                      // empty, or one per position (interpolated shading normals)
    std::vector<Vec2f> uvs;                          // empty, or one per position
    std::vector<std::array<uint32_t, 3>> triangles;  // indices into positions
};

// What a loader noticed but could repair; the scene loader reports these once to the user.
struct MeshLoadReport {
    size_t degenerateTrianglesRemoved = 0;
};

// Each loader throws lt::Error("FILE: what is wrong") for a missing or unreadable file, a malformed or
// truncated one, indices out of range, NaN or Inf in positions, normals or uvs, and a mesh without any
// non-degenerate triangle. Degenerate (zero-area) triangles are removed and counted in the report.
TriangleMesh loadObj(const std::string& filename, MeshLoadReport& report);
TriangleMesh loadPly(const std::string& filename, MeshLoadReport& report);
// Mitsuba's .serialized format (zlib-compressed, several meshes per file with an offset dictionary at
// the end); shapeIndex selects the mesh.
TriangleMesh loadSerialized(const std::string& filename, int shapeIndex, MeshLoadReport& report);

// The shared validation step of every loader: checks indices, finiteness, drops degenerate triangles.
void validateMesh(TriangleMesh& mesh, const std::string& filename, MeshLoadReport& report);

} // namespace lt
