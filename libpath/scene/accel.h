// The ray-tracing acceleration structure: one Embree 3 scene for all geometry (portals are kept out
// of it by the caller). Triangle meshes go in as Embree triangles; spheres and disks as user geometry
// intersected in double precision by Shape::intersectAnalytic.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "scene/ray.h"
#include "scene/shape.h"

namespace lt {

struct RayHit {
    int shape = -1;
    uint32_t prim = 0;
    Vec2 coords;      // barycentrics (b1, b2) for triangles; uv for analytic shapes
    double t = 0;
};

class EmbreeAccel {
public:
    EmbreeAccel();
    ~EmbreeAccel();
    EmbreeAccel(EmbreeAccel&&) noexcept;
    EmbreeAccel& operator=(EmbreeAccel&&) noexcept;
    EmbreeAccel(const EmbreeAccel&) = delete;
    EmbreeAccel& operator=(const EmbreeAccel&) = delete;

    // Build over shapes[i] for every i with include[i]; shape indices in hits refer to `shapes`.
    // The shapes must outlive the accelerator (user geometry keeps pointers to them). `robust`: Embree's
    // robust traversal, as every scene is built; false only for lt-bench-rays to measure what it costs.
    void build(const std::vector<Shape>& shapes, const std::vector<bool>& include, bool robust = true);

    [[nodiscard]] std::optional<RayHit> intersect(const Ray& ray) const;
    [[nodiscard]] bool occluded(const Ray& ray) const;

    // Rays traced so far by all threads (closest-hit and shadow). Each thread counts privately and adds
    // its count here every few thousand rays and at flushRayCount(); benchmarks read it.
    [[nodiscard]] static uint64_t rayCount();
    static void flushRayCount();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace lt
