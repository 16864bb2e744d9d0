#include "path/vertex.h"

#include "bsdf/shading_correction.h"
#include "math/constants.h"
#include "scene/measure.h"

namespace lt {

bool PathVertex::isConnectible() const {
    switch (type) {
    case VertexType::Camera:
        return true;
    case VertexType::Light:
        return emitter == nullptr || !(emitter->flags() & EmitterDeltaDirection);
    case VertexType::Surface:
        return bsdf && (bsdf->hasDiffuse() || bsdf->hasGlossy());
    }
    return false;
}

Vec3 PathVertex::directionTo(const PathVertex& next) const {
    if (infinite) return si.ng;            // an environment vertex sends light along its travel direction
    if (next.infinite) return -next.si.ng; // toward the sky, against the light's travel
    return normalize(next.si.p - si.p);
}

Spectrum PathVertex::f(const PathVertex& next, Transport mode) const {
    if (type != VertexType::Surface || !bsdf) return {};
    return worldBsdf().eval(wi, directionTo(next), mode);
}

double PathVertex::convertDensity(double pdf, const PathVertex& next) const {
    // Directions to an environment vertex keep their solid-angle measure (pbrt-v3 ConvertDensity).
    if (next.infinite) return pdf;
    // An environment vertex's rays are parallel: the density is one on the plane perpendicular to them,
    // and reaches `next` as area density times |cos| there (no distance).
    if (infinite) return next.isOnSurface() ? pdf * std::abs(dot(next.si.ng, si.ng)) : pdf;
    return pdfSolidAngleToArea(pdf, si.p, next.si.p, next.isOnSurface() ? next.si.ng : Vec3());
}

double PathVertex::pdf(const Scene& scene, const PathVertex* prev, const PathVertex& next) const {
    if (type == VertexType::Light) return pdfLight(scene, next);
    const Vec3 wn = directionTo(next);
    double pdfDir = 0;
    if (type == VertexType::Camera) {
        double pdfPos = 0;
        scene.camera.pdfEmission(si.p, wn, pdfPos, pdfDir);
    } else {
        if (!bsdf || !prev) return 0;
        pdfDir = worldBsdf().pdf(directionTo(*prev), wn);
    }
    return convertDensity(pdfDir, next);
}

double PathVertex::pdfLight(const Scene& scene, const PathVertex& next) const {
    // Environment emission starts uniformly on the scene's disk perpendicular to the direction (emitter.h).
    if (infinite) return convertDensity(scene.sceneDisk().pdf(), next);
    if (!emitter) return 0;
    const Vec3 w = directionTo(next);
    double pdfPos = 0, pdfDir = 0;
    emitter->pdfEmission(si.p, isOnSurface() ? si.ng : Vec3(), w, pdfPos, pdfDir);
    return convertDensity(pdfDir, next);
}

double PathVertex::pdfLightOrigin(const Scene& scene, const PathVertex& next) const {
    if (infinite) return infiniteLightDensity(scene, -si.ng);
    if (!emitter || emitterIndex < 0) return 0;
    double pdfPos = 0, pdfDir = 0;
    emitter->pdfEmission(si.p, isOnSurface() ? si.ng : Vec3(), directionTo(next), pdfPos, pdfDir);
    return scene.emitterSelection.pmf(size_t(emitterIndex)) * pdfPos;
}

Spectrum PathVertex::Le(const Scene& scene, const PathVertex& toward) const {
    // A directional light's vertex: its one direction, the delta stripped.
    if (infinite && emitter && (emitter->flags() & EmitterDeltaDirection)) return emitter->irradiance();
    if (infinite) {
        Spectrum sum;
        for (int e : scene.environmentEmitters)
            sum += scene.emitters[size_t(e)]->evalEnvironment(-si.ng);
        return sum;
    }
    if (!emitter) return {};
    if (type == VertexType::Light && (emitter->flags() & EmitterDeltaPosition))
        return emitter->intensity(directionTo(toward));
    return emitter->evalSurface(si.p, si.ng, directionTo(toward));
}

double geometryTerm(const PathVertex& a, const PathVertex& b) {
    // A vertex at infinity is a direction, measured in solid angle: the edge to it keeps the cosine at
    // the finite end alone (the measure of pdfLight and convertDensity).
    if (a.infinite || b.infinite) {
        const PathVertex& finite = a.infinite ? b : a;
        if (a.infinite && b.infinite) return 0;
        return finite.isOnSurface() ? std::abs(dot(finite.si.ng, a.directionTo(b))) : 1.0;
    }
    const Vec3 d = b.si.p - a.si.p;
    const double dist2 = lengthSquared(d);
    if (!(dist2 > 0)) return 0;
    const Vec3 w = d / std::sqrt(dist2);
    double g = 1.0 / dist2;
    if (a.isOnSurface()) g *= std::abs(dot(a.si.ng, w));
    if (b.isOnSurface()) g *= std::abs(dot(b.si.ng, w));
    return g;
}

bool unoccluded(const Scene& scene, const RayEndpoint& a, const RayEndpoint& b) {
    return !scene.occluded(spawnRayTo(a, b));
}

bool escapes(const Scene& scene, const RayEndpoint& from, const Vec3& dir) {
    return !scene.occluded(spawnRay(from, dir));
}

bool visible(const Scene& scene, const PathVertex& a, const PathVertex& b) {
    if (a.infinite) return visible(scene, b, a);
    const RayEndpoint ea = a.isOnSurface() ? a.si.endpoint() : RayEndpoint{a.si.p, {}, 0};
    if (b.infinite) return escapes(scene, ea, a.directionTo(b));
    return unoccluded(scene, ea, b.isOnSurface() ? b.si.endpoint() : RayEndpoint{b.si.p, {}, 0});
}

std::optional<PathVertex> asLightVertex(const Scene& scene, const PathVertex& hit) {
    if (!hit.emitter || hit.emitter->shape < 0) return std::nullopt;
    return lightVertexAt(scene, size_t(hit.emitterIndex), hit.si.p, hit.si.ng, hit.si.prim, hit.si.coords);
}

PathVertex environmentVertex(const Scene& scene, const Vec3& origin, const Vec3& dir) {
    PathVertex v;
    v.type = VertexType::Light;
    v.infinite = true;
    v.emitterIndex = scene.environmentEmitters.front();
    v.emitter = scene.emitters[size_t(v.emitterIndex)].get();
    v.si.ng = -dir;
    v.si.p = scene.sceneDisk().beyond(origin, dir);
    return v;
}

PathVertex surfaceVertex(const Scene& scene, const SurfaceInteraction& si) {
    PathVertex v;
    setSurfaceVertex(scene, SurfaceInteraction(si), v);
    return v;
}

void setSurfaceVertex(const Scene& scene, SurfaceInteraction&& si, PathVertex& v) {
    v.type = VertexType::Surface;
    v.si = std::move(si);
    v.bsdf = scene.bsdfOf(v.si);
    v.emitterIndex = scene.shapes[size_t(v.si.shape)].emitter;
    // Reset too: a vertex moved off an emitting shape (HSLT's jumps) must not keep its old emitter.
    v.emitter = v.emitterIndex >= 0 ? scene.emitters[size_t(v.emitterIndex)].get() : nullptr;
}

PathVertex lightVertexAt(const Scene& scene, size_t index, const Vec3& p, const Vec3& nOrTravel, uint32_t prim,
                         const Vec2& coords) {
    const Emitter& e = *scene.emitters[index];
    PathVertex v;
    v.type = VertexType::Light;
    v.emitter = &e;
    v.emitterIndex = int(index);
    v.infinite = e.isInfinite();
    if (e.shape >= 0) {
        v.si = scene.shapes[size_t(e.shape)].surfaceAt(prim, coords);
        v.si.shape = e.shape;
    } else {
        v.si.p = p;
        v.si.ng = nOrTravel;
    }
    return v;
}

PathVertex directLightVertex(const Scene& scene, size_t index, const DirectSample& ds) {
    const bool infinite = scene.emitters[index]->isInfinite();
    PathVertex v = lightVertexAt(scene, index, ds.p, infinite ? -ds.wi : ds.n, ds.prim, ds.coords);
    v.beta = ds.value / (ds.pdf * scene.emitterSelection.pmf(index));
    return v;
}

double infiniteLightDensity(const Scene& scene, const Vec3& w) {
    double pdf = 0;
    for (int e : scene.environmentEmitters)
        pdf += scene.emitterSelection.pmf(size_t(e)) * scene.emitters[size_t(e)]->pdfDirect(Vec3(), Vec3(), Vec3(), w);
    return pdf;
}

} // namespace lt
