#include "sampling/path_tracer.h"

#include "sampling/camera_walk.h"
#include "sampling/lens_sample.h"
#include "util/error.h"

namespace lt {

PathTracer::PathTracer(const Scene& scene, PathSettings settings) : scene_(scene), settings_(settings) {
    settings_.check();
}

namespace {

// What the path tracer does along the walk (sampling/camera_walk.h): emission found by BSDF sampling and the light
// samples, combined by MIS.
class Accumulate {
public:
    Accumulate(const Scene& scene, MisHeuristic mis, const Vec3& eye) : scene_(scene), mis_(mis), prevP_(eye) {}

    [[nodiscard]] const Spectrum& radiance() const { return L_; }

    void escaped(int, const Ray& ray, const Spectrum& beta) {
        for (int e : scene_.environmentEmitters) {
            const Emitter& em = *scene_.emitters[size_t(e)];
            const Spectrum Le = em.evalEnvironment(ray.d);
            if (Le.isBlack()) continue;
            const double w =
                prevDelta_ ? 1.0
                           : misWeight2(mis_, prevPdf_,
                                        scene_.emitterSelection.pmf(size_t(e)) * em.pdfDirect(prevP_, {}, {}, ray.d));
            L_ += beta * Le * w;
        }
    }

    void hit(int, const SurfaceInteraction& si, const Ray& ray, const Spectrum& beta) {
        const int emitter = scene_.shapes[size_t(si.shape)].emitter;
        if (emitter < 0) return;
        const Emitter& em = *scene_.emitters[size_t(emitter)];
        const Spectrum Le = em.evalSurface(si.p, si.ng, -ray.d);
        if (Le.isBlack()) return;
        const double w =
            prevDelta_
                ? 1.0
                : misWeight2(mis_, prevPdf_,
                             scene_.emitterSelection.pmf(size_t(emitter)) * em.pdfDirect(prevP_, si.p, si.ng, ray.d));
        L_ += beta * Le * w;
    }

    void nextEvent(const SurfaceInteraction& si, const WorldBsdf& wb, const Vec3& wi, const NextEvent& light,
                   const Spectrum& beta) {
        if (!light.emitter) return;
        const Emitter& em = *light.emitter;
        const DirectSample& ds = light.sample;
        if (!(ds.pdf > 0) || ds.value.isBlack()) return;
        const Spectrum f = wb.eval(wi, ds.wi, Transport::Radiance) * std::abs(dot(ds.wi, si.ng));
        if (f.isBlack()) return;
        // Visibility needs only the light point, not its differential geometry.
        const bool free = em.isInfinite() ? escapes(scene_, si.endpoint(), ds.wi)
                                          : unoccluded(scene_, si.endpoint(), {ds.p, ds.n, ds.magnitude});
        if (!free) return;
        const double pdf = ds.pdf * scene_.emitterSelection.pmf(light.index);
        const double w = em.isDelta() ? 1.0 : misWeight2(mis_, pdf, wb.pdf(wi, ds.wi));
        L_ += beta * f * ds.value * (w / pdf);
    }

    std::optional<Spectrum> scattered(const SurfaceInteraction& si, const WorldBsdf&, const BsdfSample& bs) {
        prevDelta_ = bs.lobe & LobeDelta;
        prevPdf_ = bs.pdf;
        prevP_ = si.p;
        return bs.weight;
    }

    void survived(double) {}

private:
    const Scene& scene_;
    MisHeuristic mis_;
    Spectrum L_;
    // The previous scattering: where it happened, its solid-angle density, and whether it was a delta
    // lobe (then an emitter hit cannot have been sampled by next-event estimation: weight 1).
    Vec3 prevP_;
    double prevPdf_ = 0;
    bool prevDelta_ = true;
};

} // namespace

Spectrum PathTracer::sample(const Vec2& raster, SampleGenerator& sampler, SampleHealth& health) const {
    sampler.startStream(SampleGenerator::CameraStream);
    const Ray ray = scene_.camera.generateRay(raster, sampleLensPoint(scene_.camera, sampler));
    Accumulate path(scene_, settings_.mis, ray.o);
    walkFromCamera(scene_, settings_, ray, scene_.intersect(ray), sampler, path);
    if (!path.radiance().isFinite()) {
        ++health.nonFinite;
        return {};
    }
    return path.radiance();
}

const EstimatorKind PathTracer::Kind{
    "pt",
    "path tracing with next-event estimation (MIS of BSDF and light samples)",
    {misOption()},
    {},
    [](const Scene& scene, const PathSettings& paths, const OptionValues& values) -> std::unique_ptr<PixelEstimator> {
        return std::make_unique<PathTracer>(scene, withMis(paths, values));
    },
    {}};

} // namespace lt
