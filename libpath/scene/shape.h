// Shapes in world space. Triangle meshes (obj, ply, serialized, and Mitsuba's rectangle and cube, which
// are meshes) and two analytic shapes, sphere and disk, which keep their exact normals and curvature
// for the manifold walks instead of being tessellated.
#pragma once

#include <memory>
#include <string>

#include "math/distribution.h"
#include "math/transform.h"
#include "scene/interaction.h"
#include "scene/mesh.h"
#include "texture/texture.h"

namespace lt {

struct Bounds3 {
    Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    void expand(const Vec3& p) {
        lo = min(lo, p);
        hi = max(hi, p);
    }
    void expand(const Bounds3& b) {
        lo = min(lo, b.lo);
        hi = max(hi, b.hi);
    }
    [[nodiscard]] bool valid() const { return lo.x <= hi.x; }
    [[nodiscard]] Vec3 center() const { return (lo + hi) * 0.5; }
    [[nodiscard]] Vec3 extent() const { return hi - lo; }
    [[nodiscard]] double diagonal() const { return valid() ? length(hi - lo) : 0.0; }
};

// A point sampled on a surface, with its density with respect to surface area.
struct PositionSample {
    Vec3 p, n;
    Vec2 coords;
    uint32_t prim = 0;
    double pdfArea = 0;
    double magnitude = 0;   // as SurfaceInteraction::magnitude
};

class Shape {
public:
    enum class Kind { Triangles, Sphere, Disk };

    // mesh is in world space already; flipNormals reverses the geometric and shading normals.
    static Shape triangles(TriangleMesh mesh, bool flipNormals);
    static Shape sphere(const Vec3& center, double radius, bool flipNormals);
    // Mitsuba's disk: the unit disk in the local z = 0 plane, normal +z, placed by toWorld.
    static Shape disk(const Transform& toWorld, bool flipNormals);

    [[nodiscard]] Kind kind() const { return kind_; }
    [[nodiscard]] const TriangleMesh& mesh() const { return mesh_; }
    [[nodiscard]] const Vec3& center() const { return center_; }
    [[nodiscard]] double radius() const { return radius_; }
    [[nodiscard]] const Transform& toWorld() const { return toWorld_; }
    [[nodiscard]] bool flipNormals() const { return flip_; }
    [[nodiscard]] double area() const { return area_; }
    [[nodiscard]] const Bounds3& bounds() const { return bounds_; }
    [[nodiscard]] size_t primitiveCount() const { return kind_ == Kind::Triangles ? mesh_.triangles.size() : 1; }
    [[nodiscard]] bool hasShadingNormals() const { return kind_ != Kind::Triangles || !mesh_.normals.empty(); }

    // Full differential geometry at a point given by (prim, coords): barycentrics (b1, b2) for
    // triangles, uv for analytic shapes, with the bump map's shading frame (bump). The same call rebuilds a
    // stored path vertex.
    [[nodiscard]] SurfaceInteraction surfaceAt(uint32_t prim, const Vec2& coords) const;
    // Just the position, geometric normal (oriented exactly as surfaceAt orients it) and magnitude at
    // (prim, coords): what sampling a point and testing its visibility need, without the differential
    // geometry.
    [[nodiscard]] RayEndpoint pointAt(uint32_t prim, const Vec2& coords) const;
    // Coordinates of a world point on an analytic shape (sphere, disk) for surfaceAt.
    [[nodiscard]] Vec2 analyticCoords(const Vec3& p) const;
    // Uniform point on the surface (density 1/area).
    [[nodiscard]] PositionSample samplePosition(const Vec2& u) const;

    // Analytic ray intersection in double (sphere, disk); returns the ray distance or a negative value.
    [[nodiscard]] double intersectAnalytic(const Vec3& o, const Vec3& d, double tmin, double tmax) const;

    // Scene bookkeeping, set by the loader.
    int bsdf = -1;
    std::shared_ptr<const Texture> bump; // the displacement of its BSDF's bumpmap, if any (scene/bump_frame.h)
    int emitter = -1;
    bool portal = false;
    std::string type;      // Mitsuba plugin name, e.g. "obj", "rectangle"
    std::string id;        // XML id, if any
    std::string origin;    // "FILE:LINE" of the <shape> element, for messages

private:
    void finishTriangles();

    Kind kind_ = Kind::Triangles;
    TriangleMesh mesh_;
    DiscreteDistribution triangleAreas_;
    // Per triangle, its unit geometric normal as pointAt returns it, computed once: pointAt runs on every
    // hit and every light sample. Flipped by flipNormals, and turned to the side of the shading normals
    // when all three vertex normals lie clearly on one side; where they do not (sideVaries_, only for meshes
    // with normals), and at coordinates outside the triangle, pointAt decides the side at the point.
    std::vector<Vec3> geometricNormals_;
    std::vector<bool> sideVaries_;
    // Triangles whose three vertex normals differ: only there does the shading normal turn across the
    // triangle (elsewhere dn/du = dn/dv = 0, and surfaceAt leaves them at zero without computing them).
    std::vector<bool> normalsVary_;

    // pointAt of a triangle whose vertices (p0, p1, p2) are read already.
    [[nodiscard]] RayEndpoint trianglePoint(uint32_t prim, const Vec3& p0, const Vec3& p1, const Vec3& p2, double b0,
                                            double b1, double b2) const;
    Vec3 center_;
    double radius_ = 0;
    Transform toWorld_;
    bool flip_ = false;
    double area_ = 0;
    Bounds3 bounds_;
};

// Mitsuba's built-in meshes, in their local frames: rectangle [-1,1]^2 at z = 0 with normal +z and uv
// in [0,1]^2; cube [-1,1]^3 with outward face normals (24 vertices, each face its own uv square).
TriangleMesh makeRectangleMesh();
TriangleMesh makeCubeMesh();
// Apply toWorld to a mesh: positions as points, normals with the inverse transpose (normalized).
void transformMesh(TriangleMesh& mesh, const Transform& toWorld);

} // namespace lt
