#include "sampling/path_tracer.h"

#include "bsdf/shading_correction.h"
#include "math/error.h"
#include "path/scatter.h"
#include "sampling/lens_sample.h"

namespace lt {

PathTracer::PathTracer(const Scene& scene, PathSettings settings) : scene_(scene), settings_(settings) {
    if (settings_.maxDepth == 0 || settings_.maxDepth < -1) throw Error("maxDepth must be -1 (unbounded) or at least 1");
}

Spectrum PathTracer::sample(const Vec2& raster, SampleGenerator& sampler, SampleHealth& health) const {
    sampler.startStream(SampleGenerator::CameraStream);
    const PerspectiveCamera& camera = scene_.camera;
    Ray ray = camera.generateRay(raster, sampleLensPoint(camera, sampler));
    Spectrum L, beta(1.0);
    // The previous scattering: where it happened, its solid-angle density, and whether it was a delta
    // lobe (then an emitter hit cannot have been sampled by next-event estimation: weight 1).
    Vec3 prevP = ray.o;
    double prevPdf = 0;
    bool prevDelta = true;
    double etaScale = 1;   // product of eta^2 over refractions (see russianRouletteSurvival)
    const auto& sel = scene_.emitterSelection;
    for (int edges = 1;; ++edges) {
        const auto hit = scene_.intersect(ray);
        if (!hit) {
            for (int e : scene_.environmentEmitters) {
                const Emitter& em = *scene_.emitters[size_t(e)];
                const Spectrum Le = em.evalEnvironment(ray.d);
                if (Le.isBlack()) continue;
                const double w = prevDelta ? 1.0
                                           : misWeight2(settings_.mis, prevPdf,
                                                        sel.pmf(size_t(e)) * em.pdfDirect(prevP, {}, {}, ray.d));
                L += beta * Le * w;
            }
            break;
        }
        const SurfaceInteraction& si = *hit;
        const Shape& shape = scene_.shapes[size_t(si.shape)];
        if (shape.emitter >= 0) {
            const Emitter& em = *scene_.emitters[size_t(shape.emitter)];
            const Spectrum Le = em.evalSurface(si.p, si.ng, -ray.d);
            if (!Le.isBlack()) {
                const double w = prevDelta ? 1.0
                                           : misWeight2(settings_.mis, prevPdf,
                                                        sel.pmf(size_t(shape.emitter)) * em.pdfDirect(prevP, si.p, si.ng, ray.d));
                L += beta * Le * w;
            }
        }
        if (settings_.maxDepth >= 0 && edges >= settings_.maxDepth) break;
        const Bsdf* bsdf = scene_.bsdfOf(si);
        if (!bsdf) break;
        const WorldBsdf wb{*bsdf, si.shading, si.ng, si.uv};
        const Vec3 wi = -ray.d;

        // Next-event estimation through the shared direct-light vertex (path/vertex.h).
        sampler.startStream(SampleGenerator::ConnectStream);
        const double uLight = sampler.next1D();
        const Vec2 uDirect = sampler.next2D();
        if ((bsdf->hasDiffuse() || bsdf->hasGlossy()) && !sel.empty()) {
            const size_t index = sel.sample(uLight);
            const Emitter& em = *scene_.emitters[index];
            const DirectSample ds = em.sampleDirect(si.p, uDirect);
            if (ds.pdf > 0 && !ds.value.isBlack()) {
                const Spectrum f = wb.eval(wi, ds.wi, Transport::Radiance) * std::abs(dot(ds.wi, si.ng));
                if (!f.isBlack()) {
                    // Visibility needs only the light point, not its differential geometry.
                    const bool free = em.isInfinite() ? escapes(scene_, si.endpoint(), ds.wi)
                                                      : unoccluded(scene_, si.endpoint(), {ds.p, ds.n, ds.magnitude});
                    if (free) {
                        const double pdf = ds.pdf * sel.pmf(index);
                        const double w = em.isDelta() ? 1.0 : misWeight2(settings_.mis, pdf, wb.pdf(wi, ds.wi));
                        L += beta * f * ds.value * (w / pdf);
                    }
                }
            }
        }

        sampler.startStream(SampleGenerator::CameraStream);
        const double uLobe = sampler.next1D();
        const auto bs = sampleScattering(wb, wi, Transport::Radiance, uLobe, sampler.next2D());
        if (!bs) break;
        beta *= bs->weight;
        if (bs->lobe & LobeTransmission) etaScale *= bs->eta * bs->eta;
        prevDelta = bs->lobe & LobeDelta;
        prevPdf = bs->pdf;
        prevP = si.p;
        if (edges >= settings_.rrDepth) {
            const double q = russianRouletteSurvival(beta, etaScale);
            if (!(sampler.next1D() < q)) break;
            beta /= q;
        }
        ray = spawnRay(si.endpoint(), bs->wo);
    }
    if (!L.isFinite()) {
        ++health.nonFinite;
        return {};
    }
    return L;
}

} // namespace lt
