#include "path/scatter.h"

namespace lt {

std::optional<BsdfSample> sampleScattering(const WorldBsdf& bsdf, const Vec3& wi, Transport mode, double uLobe,
                                           const Vec2& u) {
    auto bs = bsdf.sample(wi, mode, uLobe, u);
    if (!bs || bs->weight.isBlack()) return std::nullopt;
    return bs;
}

std::optional<BsdfSample> sampleScattering(PathVertex& v, const Vec3& wi, Transport mode, double uLobe, const Vec2& u) {
    auto bs = sampleScattering(v.worldBsdf(), wi, mode, uLobe, u);
    if (!bs) return std::nullopt;
    v.lobe = bs->lobe;
    v.delta = (bs->lobe & LobeDelta) != 0;
    return bs;
}

Ray rayFrom(const PathVertex& from, const Vec3& dir) {
    return from.isOnSurface() ? spawnRay(from.si.endpoint(), dir) : Ray{from.si.p, dir};
}

std::optional<PathVertex> traceVertex(const Scene& scene, const Ray& ray) {
    const auto hit = scene.intersectHit(ray);
    if (!hit) return std::nullopt;
    std::optional<PathVertex> v(std::in_place);
    setSurfaceVertex(scene, scene.interactionAt(*hit), *v);
    return v;
}

} // namespace lt
