#include "mcmc/mutations/trace.h"

namespace lt {

std::optional<PathVertex> traceVertex(const Scene& scene, const Ray& ray) {
    const auto hit = scene.intersect(ray);
    if (!hit) return std::nullopt;
    return surfaceVertex(scene, *hit);
}

Ray rayFrom(const PathVertex& from, const Vec3& dir) {
    return from.isOnSurface() ? spawnRay(from.si.endpoint(), dir) : Ray{from.si.p, dir};
}

} // namespace lt
