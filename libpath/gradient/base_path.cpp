#include "gradient/base_path.h"

#include "path/scatter.h"
#include "path/vertex.h"
#include "scene/scene.h"

namespace lt {

bool connectableLobe(const Bsdf& bsdf, const Vec2& uv, bool deltaLobe, double threshold) {
    if (deltaLobe || !samplesLights(bsdf)) return false;
    return bsdf.hasDiffuse() || bsdf.roughness(uv) > threshold;
}

Spectrum environmentRadiance(const Scene& scene, const Vec3& dir) {
    Spectrum L;
    for (int e : scene.environmentEmitters)
        if (!scene.emitters[size_t(e)]->isDelta()) L += scene.emitters[size_t(e)]->evalEnvironment(dir);
    return L;
}

double environmentPdf(const Scene& scene, const Vec3& ref, const Vec3& dir) {
    double pdf = 0;
    for (int e : scene.environmentEmitters) {
        const Emitter& em = *scene.emitters[size_t(e)];
        if (!em.isDelta()) pdf += scene.emitterSelection.pmf(size_t(e)) * em.pdfDirect(ref, {}, {}, dir);
    }
    return pdf;
}

namespace {

BaseVertex vertexAt(const Scene& scene, SurfaceInteraction&& si, const Vec3& wi) {
    BaseVertex v;
    v.si = std::move(si);
    v.bsdf = scene.bsdfOf(v.si);
    v.emitter = scene.shapes[size_t(v.si.shape)].emitter;
    v.wi = wi;
    return v;
}

} // namespace

std::optional<BaseVertex> primaryVertex(const Scene& scene, const Vec2& raster, const Vec3& lens) {
    const Ray ray = scene.camera.generateRay(raster, lens);
    auto hit = scene.intersect(ray);
    if (!hit) return std::nullopt;
    return vertexAt(scene, std::move(*hit), -ray.d);
}

BasePath traceBasePath(const Scene& scene, const PathSettings& settings, double shiftThreshold, const Vec2& raster,
                       const Vec3& lens, std::optional<BaseVertex> primary, SampleGenerator& sampler) {
    BasePath path;
    path.raster = raster;
    path.rrDepth = settings.rrDepth;
    if (!primary) {
        const Vec3 d = scene.camera.generateRay(raster, lens).d;
        for (int e : scene.environmentEmitters)
            path.direct += scene.emitters[size_t(e)]->evalEnvironment(d);
        return path;
    }
    if (primary->emitter >= 0)
        path.direct = scene.emitters[size_t(primary->emitter)]->evalSurface(primary->si.p, primary->si.ng, primary->wi);
    path.vertices.push_back(std::move(*primary));
    const auto& sel = scene.emitterSelection;
    Spectrum beta(1.0);
    double etaScale = 1;
    for (int edges = 1;; ++edges) {
        BaseVertex& v = path.vertices.back();
        if (settings.maxDepth >= 0 && edges >= settings.maxDepth) break;
        if (!v.bsdf) break;
        const WorldBsdf wb = v.worldBsdf();
        v.connectable = connectableLobe(*v.bsdf, v.si.uv, false, shiftThreshold);

        sampler.startStream(SampleGenerator::ConnectStream);
        const double uLight = sampler.next1D();
        const Vec2 uDirect = sampler.next2D();
        if (samplesLights(*v.bsdf) && !sel.empty()) {
            const size_t index = sel.sample(uLight);
            const Emitter& em = *scene.emitters[index];
            const DirectSample ds = em.sampleDirect(v.si.p, uDirect);
            // Kept even when no light arrives here (a one-sided light seen from behind): the same point may
            // light an offset vertex, and this technique's density is in the weights of those shifts.
            if (ds.pdf > 0) {
                BaseLightSample& l = v.light;
                l.emitter = int(index);
                l.p = ds.p;
                l.n = ds.n;
                l.magnitude = ds.magnitude;
                l.wo = ds.wi;
                l.delta = em.isDelta();
                l.infinite = em.isInfinite();
                l.Le = l.infinite && !l.delta ? environmentRadiance(scene, ds.wi) : ds.value;
                l.pdfLight = l.infinite && !l.delta ? environmentPdf(scene, v.si.p, ds.wi) : ds.pdf * sel.pmf(index);
                // Traced even where f_s is zero here: visibility decides whether a BSDF sample could
                // produce this path, which the weights of its shifts need (gradient/shift_mapping.h).
                l.visible = l.infinite ? escapes(scene, v.si.endpoint(), ds.wi)
                                       : unoccluded(scene, v.si.endpoint(), {ds.p, ds.n, ds.magnitude});
            }
        }

        sampler.startStream(SampleGenerator::CameraStream);
        const double uLobe = sampler.next1D();
        const auto bs = sampleScattering(wb, v.wi, Transport::Radiance, uLobe, sampler.next2D());
        if (!bs) break;
        v.wo = bs->wo;
        v.lobe = bs->lobe;
        v.pdf = bs->pdf;
        // Non-delta values from eval(), as the shift evaluates its offsets (BaseVertex::scatter).
        v.fCos = v.delta() ? bs->weight * bs->pdf : v.scatter(v.wi, v.wo).fCos;
        if (v.fCos.isBlack() || !(v.pdf > 0)) break;
        beta *= v.fCos / v.pdf;
        if (bs->lobe & LobeTransmission) etaScale *= bs->eta * bs->eta;
        if (edges >= settings.rrDepth) {
            const double q = russianRouletteSurvival(beta, etaScale);
            if (!(sampler.next1D() < q)) break;
            beta /= q;
            v.survival = q;
        }
        v.scattered = true;
        auto hit = scene.intersect(spawnRay(v.si.endpoint(), v.wo));
        if (!hit) {
            v.escaped = true;
            break;
        }
        const Vec3 wi = -v.wo;
        path.vertices.push_back(vertexAt(scene, std::move(*hit), wi));
    }
    return path;
}

} // namespace lt
