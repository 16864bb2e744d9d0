// The path tracer's walk from the camera (Veach 1997, Sec. 9.2; pbrt's and Mitsuba's path tracers): at every
// vertex whose BSDF has a non-delta lobe a light sample (next-event estimation), then a BSDF sample to go on,
// then Russian roulette from the throughput after rrDepth edges. The light sample draws its numbers from the
// connect stream, the rest from the camera stream (sampling/sample_generator.h), so a light sample never shifts
// the numbers of the walk.
//
// One walk for the two estimators that must sample exactly the same paths: the path tracer (sampling/
// path_tracer.h), which adds up what it finds, and the base paths of the gradient-domain estimators
// (gradient/base_path.h), which keep every vertex and decision for the shift mapping. What is done with a vertex
// is the visitor's:
//   void hit(int edges, const SurfaceInteraction& si, const Ray& ray, const Spectrum& beta)
//       a vertex, reached along `ray` after `edges` edges with throughput `beta` (the camera's vertex excluded);
//   void escaped(int edges, const Ray& ray, const Spectrum& beta)
//       the ray of edge `edges` left the scene;
//   void nextEvent(const SurfaceInteraction& si, const WorldBsdf& bsdf, const Vec3& wi, const NextEvent& light,
//                  const Spectrum& beta)
//       the vertex goes on (within the depth bound, with a BSDF; wi toward the previous vertex); its light sample,
//       if one was drawn;
//   std::optional<Spectrum> scattered(const SurfaceInteraction& si, const WorldBsdf& bsdf, const BsdfSample& s)
//       the BSDF sample the walk goes on with: the factor the throughput takes from it, or nothing to end the walk;
//   void survived(double q)
//       the walk went on past Russian roulette with probability q.
#pragma once

#include <optional>

#include "bsdf/shading_correction.h"
#include "path/scatter.h"
#include "sampling/path_settings.h"
#include "sampling/sample_generator.h"
#include "scene/scene.h"

namespace lt {

// Whether a BSDF does next-event estimation: it has a non-delta lobe.
[[nodiscard]] inline bool samplesLights(const Bsdf& bsdf) { return bsdf.hasDiffuse() || bsdf.hasGlossy(); }

// The light sample of next-event estimation at a vertex: an emitter chosen by the scene's emitter selection and
// a point (or direction) on it.
struct NextEvent {
    const Emitter* emitter = nullptr; // null: none drawn (only delta lobes here, or no emitters in the scene)
    size_t index = 0;                 // the emitter's index into Scene::emitters
    DirectSample sample;
};

// Walks from the camera ray `ray`, whose first hit (nothing: it escaped) the caller found: base paths share
// their primary hits with the shifts to other pixels.
template <class Visitor>
void walkFromCamera(const Scene& scene, const PathSettings& settings, Ray ray, std::optional<SurfaceInteraction> hit,
                    SampleGenerator& sampler, Visitor& visitor) {
    Spectrum beta(1.0);
    double etaScale = 1; // product of eta^2 over refractions (see russianRouletteSurvival)
    const auto& selection = scene.emitterSelection;
    for (int edges = 1;; ++edges) {
        if (!hit) {
            visitor.escaped(edges, ray, beta);
            return;
        }
        const SurfaceInteraction& si = *hit;
        visitor.hit(edges, si, ray, beta);
        if (settings.maxDepth >= 0 && edges >= settings.maxDepth) return;
        const Bsdf* bsdf = scene.bsdfOf(si);
        if (!bsdf) return;
        const WorldBsdf wb{*bsdf, si.shading, si.ng, si.uv};

        sampler.startStream(SampleGenerator::ConnectStream);
        const double uLight = sampler.next1D();
        const Vec2 uDirect = sampler.next2D();
        NextEvent light;
        if (samplesLights(*bsdf) && !selection.empty()) {
            light.index = selection.sample(uLight);
            light.emitter = scene.emitters[light.index].get();
            light.sample = light.emitter->sampleDirect(si.p, uDirect);
        }
        const Vec3 wi = -ray.d;
        visitor.nextEvent(si, wb, wi, light, beta);

        sampler.startStream(SampleGenerator::CameraStream);
        const double uLobe = sampler.next1D();
        const auto bs = sampleScattering(wb, wi, Transport::Radiance, uLobe, sampler.next2D());
        if (!bs) return;
        const std::optional<Spectrum> factor = visitor.scattered(si, wb, *bs);
        if (!factor) return;
        beta *= *factor;
        if (bs->lobe & LobeTransmission) etaScale *= bs->eta * bs->eta;
        if (edges >= settings.rrDepth) {
            const double q = russianRouletteSurvival(beta, etaScale);
            if (!(sampler.next1D() < q)) return;
            beta /= q;
            visitor.survived(q);
        }
        ray = spawnRay(si.endpoint(), bs->wo);
        hit = scene.intersect(ray);
    }
}

} // namespace lt
