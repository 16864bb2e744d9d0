#include "scene/scene.h"

#include <algorithm>

namespace lt {

std::optional<SurfaceInteraction> Scene::intersect(const Ray& ray) const {
    const auto hit = accel_.intersect(ray);
    if (!hit) return std::nullopt;
    return interactionAt(*hit);
}

SurfaceInteraction Scene::interactionAt(const RayHit& hit) const {
    SurfaceInteraction si = shapes[size_t(hit.shape)].surfaceAt(hit.prim, hit.coords);
    si.shape = hit.shape;
    si.t = hit.t;
    return si;
}

size_t Scene::triangleCount() const {
    size_t n = 0;
    for (const auto& s : shapes)
        if (s.kind() == Shape::Kind::Triangles && !s.portal) n += s.mesh().triangles.size();
    return n;
}

const Bsdf* Scene::bsdfOf(const SurfaceInteraction& si) const {
    const int b = shapes[size_t(si.shape)].bsdf;
    return b >= 0 ? bsdfs[size_t(b)].bsdf.get() : nullptr;
}

std::vector<bool> Scene::geometryShapes() const {
    std::vector<bool> geometry(shapes.size());
    for (size_t i = 0; i < shapes.size(); ++i)
        geometry[i] = !shapes[i].portal;
    return geometry;
}

void Scene::finalize() {
    std::vector<bool> include = geometryShapes();
    bounds = {};
    for (size_t i = 0; i < shapes.size(); ++i)
        if (include[i]) bounds.expand(shapes[i].bounds());
    if (!bounds.valid()) bounds.expand(Vec3(0, 0, 0));
    accel_.build(shapes, include);
    include.flip(); // now the portals
    hasPortals_ = std::find(include.begin(), include.end(), true) != include.end();
    if (hasPortals_) portals_.build(shapes, include);
    const SceneDisk disk = sceneDisk();
    std::vector<double> power;
    environmentEmitters.clear();
    for (auto& e : emitters) {
        if (e->isInfinite() && !(e->flags() & EmitterDeltaDirection)) environmentEmitters.push_back(int(&e - &emitters[0]));
        e->setSceneBounds(disk.center, disk.radius);
        power.push_back(std::max(0.0, e->power().luminance()));
    }
    emitterSelection = DiscreteDistribution(power);
}

} // namespace lt
