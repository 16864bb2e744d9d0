// The base path of the gradient-domain estimators: a path traced from the camera with next-event
// estimation, stored vertex by vertex with every sampling decision, so that the shift mapping
// (gradient/shift_mapping.h) can move it to other pixels afterwards (Kettunen et al. 2015, Sec. 5;
// [GDPR] Sec. 3.3: "store the whole base path"). It is the path tracer's own walk (sampling/camera_walk.h), so it
// samples exactly what the path tracer does: a light sample at every vertex with a non-delta lobe, a BSDF sample
// to go on, Russian roulette from the throughput after rrDepth edges.
//
// Measure: the raster position, then the solid angle of every direction leaving a vertex (Kettunen et al.
// 2015, Sec. 5.2 work in the same one). The camera's importance over its sampling density is 1 (the film
// draws raster positions from the pixel filter), so a path's value is the product of f_s |cos| of its
// scattering vertices times the emitted radiance, and its density the product of the directions' solid-angle
// densities (discrete lobe probabilities at delta vertices).
#pragma once

#include <vector>

#include "bsdf/shading_correction.h"
#include "sampling/camera_walk.h"
#include "sampling/path_settings.h"
#include "sampling/sample_generator.h"
#include "scene/interaction.h"

namespace lt {

class Scene;

// Which shifts a vertex allows (Kettunen et al. 2015, Sec. 5.2): a vertex is connectable when the lobe
// the path used there is rough enough for a reconnection to be well behaved: a non-delta lobe of a BSDF that
// has a diffuse lobe or a Beckmann-equivalent roughness above `threshold` (`--shift-threshold`, default
// 0.001 as in the public G-PT code). The same function classifies base and offset vertices, so the shift
// makes the same decision in both directions.
[[nodiscard]] bool connectableLobe(const Bsdf& bsdf, const Vec2& uv, bool deltaLobe, double threshold);

// All non-delta environment emitters as one light: choosing one of them for a light sample and then a
// direction from it draws the direction from their mixture (density: the sum of pmf x pdf), and a direction
// carries the sum of their radiance. Then a path that leaves the scene is one ending, whichever emitter
// (with one environment emitter, as the path tracer weighs it).
[[nodiscard]] Spectrum environmentRadiance(const Scene& scene, const Vec3& dir);
[[nodiscard]] double environmentPdf(const Scene& scene, const Vec3& ref, const Vec3& dir);

// The light sample of next-event estimation at a vertex.
struct BaseLightSample {
    int emitter = -1;      // index into Scene::emitters; -1: none taken
    Vec3 p, n;             // the point on the light (n zero for point lights; infinite lights: p far away)
    double magnitude = 0;  // of p's primitive, for shadow rays
    Vec3 wo;               // unit direction from the vertex toward p
    Spectrum Le;           // radiance arriving along -wo (intensity / d^2 for point lights)
    double pdfLight = 0;   // solid-angle density of wo, light selection included (1 x pmf for delta lights)
    bool delta = false;    // a delta light: BSDF sampling cannot reach it
    bool infinite = false; // environment or directional: p is a direction
    bool visible = false;  // the base path's shadow ray
};

// A vertex's effective f_s |cos| (bsdf/shading_correction.h) and BSDF density for one pair of directions.
struct VertexScatter {
    Spectrum fCos;
    double pdf = 0;
};

struct BaseVertex {
    SurfaceInteraction si;
    const Bsdf* bsdf = nullptr; // null: the path ends here
    int emitter = -1;           // the emitter on this surface, if any
    Vec3 wi;                    // unit direction toward the previous vertex
    bool connectable = false;   // its non-delta lobes (next-event estimation, reconnection target)
    BaseLightSample light;
    // The scattering sampled here when the path goes on (after Russian roulette).
    bool scattered = false;
    Vec3 wo; // world direction sampled
    Lobes lobe = LobeNone;
    Spectrum fCos;        // effective f_s |wo.ng| (delta lobes: weight x probability)
    double pdf = 0;       // solid-angle density (delta lobes: the lobe's probability)
    double survival = 1;  // Russian roulette probability applied after this vertex
    bool escaped = false; // the ray leaving along wo left the scene (no next vertex)

    [[nodiscard]] bool delta() const { return lobe & LobeDelta; }
    [[nodiscard]] WorldBsdf worldBsdf() const { return {*bsdf, si.shading, si.ng, si.uv}; }
    // The non-delta lobes from direction wi toward wo: what the base path and every shift evaluate.
    [[nodiscard]] VertexScatter scatter(const Vec3& wiWorld, const Vec3& woWorld) const {
        const WorldBsdf wb = worldBsdf();
        return {wb.eval(wiWorld, woWorld, Transport::Radiance) * std::abs(dot(woWorld, si.ng)),
                wb.pdf(wiWorld, woWorld)};
    }
};

struct BasePath {
    Vec2 raster;
    int rrDepth = 0;                  // from this many edges on it continued by Russian roulette
    Spectrum direct;                  // emitters seen directly (the "direct" plane, kept out of the gradients)
    std::vector<BaseVertex> vertices; // x_1 (the primary hit) ... ; empty when the camera ray escapes
};

// The primary hit of a raster position seen from a lens point (camera.h): its vertex (wi, BSDF, emitter
// set), or nothing when the ray escapes. Base paths start here, and the shift to another pixel starts at
// that pixel's primary hit from the same lens point (the offset path keeps the base's lens sample: the
// shift of the camera vertex is the identity, Jacobian 1).
[[nodiscard]] std::optional<BaseVertex> primaryVertex(const Scene& scene, const Vec2& raster, const Vec3& lens);

// Traces a base path from a primary vertex (nothing: the camera ray escaped) for raster position `raster`
// and lens point `lens`, with the random numbers of `sampler` in the path tracer's streams.
[[nodiscard]] BasePath traceBasePath(const Scene& scene, const PathSettings& settings, double shiftThreshold,
                                     const Vec2& raster, const Vec3& lens, std::optional<BaseVertex> primary,
                                     SampleGenerator& sampler);

} // namespace lt
