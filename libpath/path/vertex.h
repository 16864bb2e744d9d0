// A vertex of a light or camera subpath, with the densities bidirectional estimators need (Veach thesis
// ch. 10; pbrt-v3 section 16.3 is the model for the bookkeeping). Densities are AREA densities at the
// vertex, except at an environment ("infinite") light vertex, where they are solid-angle densities of
// the direction (an environment has no surface to measure area on).
#pragma once

#include <optional>

#include "bsdf/bsdf.h"
#include "bsdf/shading_correction.h"
#include "scene/interaction.h"
#include "scene/scene.h"

namespace lt {

enum class VertexType : uint8_t { Camera, Light, Surface };

struct PathVertex {
    VertexType type = VertexType::Surface;
    Spectrum beta;                    // throughput of the subpath up to and including this vertex
    SurfaceInteraction si;            // position, normals, frame (camera and point-like vertices: p only)
    const Bsdf* bsdf = nullptr;       // surface vertices
    const Emitter* emitter = nullptr; // light vertices, and surface vertices that lie on an emitter
    int emitterIndex = -1;
    Vec3 wi;               // unit direction toward the previous vertex (zero at endpoints)
    bool infinite = false; // a light vertex of the environment: si.ng holds the direction of travel
    bool delta = false;    // scattered by a delta lobe (then pdfFwd = pdfRev = 0)
    Lobes lobe = LobeNone; // the lobe sampled at this vertex
    double pdfFwd = 0;     // density of this vertex when sampled from its predecessor
    double pdfRev = 0;     // density of this vertex when sampled from its successor

    [[nodiscard]] const Vec3& p() const { return si.p; }
    [[nodiscard]] const Vec3& ng() const { return si.ng; }
    [[nodiscard]] bool isOnSurface() const { return !infinite && lengthSquared(si.ng) > 0; }
    [[nodiscard]] bool isLight() const { return type == VertexType::Light || (type == VertexType::Surface && emitter); }
    [[nodiscard]] bool isDeltaLight() const { return type == VertexType::Light && emitter && emitter->isDelta(); }
    [[nodiscard]] bool isInfiniteLight() const { return type == VertexType::Light && infinite; }
    // A vertex can be joined to another by a deterministic connection unless it scatters only through
    // delta lobes, or is a light whose direction is a delta (directional light).
    [[nodiscard]] bool isConnectible() const;

    // Unit direction from this vertex toward `next` (for an environment vertex: against its travel).
    [[nodiscard]] Vec3 directionTo(const PathVertex& next) const;
    // The BSDF of a surface vertex in world space, with the shading-normal rules (bsdf/shading_correction.h);
    // only for vertices with a BSDF.
    [[nodiscard]] WorldBsdf worldBsdf() const { return {*bsdf, si.shading, si.ng, si.uv}; }
    // The effective BSDF between wi (toward the previous vertex) and the direction toward `next`, for a
    // surface vertex (bsdf/shading_correction.h: multiply by the geometric cosine at this vertex).
    [[nodiscard]] Spectrum f(const PathVertex& next, Transport mode) const;

    // Area density (solid angle if `next` is at infinity) of sampling `next` from this vertex, given the
    // vertex before it (`prev`, may be null at endpoints).
    [[nodiscard]] double pdf(const Scene& scene, const PathVertex* prev, const PathVertex& next) const;
    // For a light vertex: the density of `next` when the light emits toward it.
    [[nodiscard]] double pdfLight(const Scene& scene, const PathVertex& next) const;
    // For a light vertex: the density of choosing this light and this point on it (area; for the
    // environment, the solid-angle density of choosing its direction), given the vertex it shines on.
    [[nodiscard]] double pdfLightOrigin(const Scene& scene, const PathVertex& next) const;
    // Radiance this (emitting) vertex sends toward `toward` (the intensity of a point or spot light, the
    // irradiance of a directional light).
    [[nodiscard]] Spectrum Le(const Scene& scene, const PathVertex& toward) const;

    // Convert a solid-angle density at this vertex into the density of `next` (area, or kept in solid
    // angle when next is at infinity); at an environment vertex, whose rays are parallel, the density is
    // one on the plane perpendicular to them. The one place for this conversion in path construction.
    [[nodiscard]] double convertDensity(double pdf, const PathVertex& next) const;
};

// The geometry term between two vertices with geometric normals (Jakob & Marschner 2012, Eq. 5), visibility
// excluded: |n_a . w| |n_b . w| / d^2, where a point without a surface contributes no cosine, and a
// vertex at infinity contributes neither cosine nor distance.
[[nodiscard]] double geometryTerm(const PathVertex& a, const PathVertex& b);
// Whether the segment between two vertices is free of occluders.
[[nodiscard]] bool visible(const Scene& scene, const PathVertex& a, const PathVertex& b);
// The same for two surface points (or points without surface: zero normal), and for a ray that must
// leave the scene (toward an environment or directional emitter).
[[nodiscard]] bool unoccluded(const Scene& scene, const RayEndpoint& a, const RayEndpoint& b);
[[nodiscard]] bool escapes(const Scene& scene, const RayEndpoint& from, const Vec3& dir);

// The vertex a ray hit: its surface, BSDF and, when the surface emits, its emitter. Path construction
// (BDPT's random walks, the Markov chains' mutations) and re-created paths all build vertices here.
[[nodiscard]] PathVertex surfaceVertex(const Scene& scene, const SurfaceInteraction& si);
// The same, filling `v` in place (no copy of the interaction): the hot loops' form.
void setSurfaceVertex(const Scene& scene, SurfaceInteraction&& si, PathVertex& v);

// A light vertex at a point emitter `index` produced: on an area emitter the full surface geometry at
// (prim, coords); otherwise the point p with normal n (zero for point-like emitters), or, for an
// environment or directional emitter, the direction the light travels in place of the normal.
[[nodiscard]] PathVertex lightVertexAt(const Scene& scene, size_t index, const Vec3& p, const Vec3& nOrTravel,
                                       uint32_t prim, const Vec2& coords);

// The light vertex of a surface vertex that lies on an area emitter (a ray that reached a light), or
// nothing when its surface does not emit.
[[nodiscard]] std::optional<PathVertex> asLightVertex(const Scene& scene, const PathVertex& hit);

// The vertex at infinity where a ray from `origin` along `dir` (unit) leaves the scene: the environment as
// one light (Le and the densities sum over every environment emitter; the first names it), travelling
// along -dir, its position a point beyond the scene's bounding sphere. Only for scenes with an environment
// emitter.
[[nodiscard]] PathVertex environmentVertex(const Scene& scene, const Vec3& origin, const Vec3& dir);

// The light vertex of a direct (next-event) sample: the point sampleDirect chose on emitter `index`,
// with its throughput value / (pdf * selection probability) and its emission-origin density. BDPT's
// s = 1 strategy and the path tracer's next-event estimation both start from it.
[[nodiscard]] PathVertex directLightVertex(const Scene& scene, size_t index, const DirectSample& ds);

// Density of the environment emitters producing direction w (pointing from the scene toward the
// sky), each weighted by its selection probability: the density of an escaped camera path's "light
// vertex" origin.
[[nodiscard]] double infiniteLightDensity(const Scene& scene, const Vec3& w);

} // namespace lt
