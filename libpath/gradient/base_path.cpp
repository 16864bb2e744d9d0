#include "gradient/base_path.h"

#include "path/vertex.h"
#include "sampling/camera_walk.h"
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

BaseVertex vertexAt(const Scene& scene, const SurfaceInteraction& si, const Vec3& wi) {
    BaseVertex v;
    v.si = si;
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
    return vertexAt(scene, *hit, -ray.d);
}

namespace {

// What a base path keeps of the walk (sampling/camera_walk.h): every vertex with its light sample and the
// scattering it went on with.
class Record {
public:
    Record(const Scene& scene, double shiftThreshold, std::optional<BaseVertex>&& primary, BasePath& path)
        : scene_(scene), shiftThreshold_(shiftThreshold), primary_(std::move(primary)), path_(path) {}

    void escaped(int edges, const Ray& ray, const Spectrum&) {
        if (edges > 1) {
            path_.vertices.back().escaped = true;
            path_.vertices.back().scattered = true;
            return;
        }
        for (int e : scene_.environmentEmitters)
            path_.direct += scene_.emitters[size_t(e)]->evalEnvironment(ray.d);
    }

    void hit(int edges, const SurfaceInteraction& si, const Ray& ray, const Spectrum&) {
        if (edges > 1) {
            path_.vertices.back().scattered = true;
            path_.vertices.push_back(vertexAt(scene_, si, -ray.d));
            return;
        }
        const BaseVertex& v = *primary_;
        if (v.emitter >= 0) path_.direct = scene_.emitters[size_t(v.emitter)]->evalSurface(v.si.p, v.si.ng, v.wi);
        path_.vertices.push_back(std::move(*primary_));
    }

    void nextEvent(const SurfaceInteraction&, const WorldBsdf&, const Vec3&, const NextEvent& light, const Spectrum&) {
        BaseVertex& v = path_.vertices.back();
        v.connectable = connectableLobe(*v.bsdf, v.si.uv, false, shiftThreshold_);
        // Kept even when no light arrives here (a one-sided light seen from behind): the same point may light an
        // offset vertex, and this technique's density is in the weights of those shifts.
        if (!light.emitter || !(light.sample.pdf > 0)) return;
        const DirectSample& ds = light.sample;
        BaseLightSample& l = v.light;
        l.emitter = int(light.index);
        l.p = ds.p;
        l.n = ds.n;
        l.magnitude = ds.magnitude;
        l.wo = ds.wi;
        l.delta = light.emitter->isDelta();
        l.infinite = light.emitter->isInfinite();
        l.Le = l.infinite && !l.delta ? environmentRadiance(scene_, ds.wi) : ds.value;
        l.pdfLight = l.infinite && !l.delta ? environmentPdf(scene_, v.si.p, ds.wi)
                                            : ds.pdf * scene_.emitterSelection.pmf(light.index);
        // Traced even where f_s is zero here: visibility decides whether a BSDF sample could produce this path,
        // which the weights of its shifts need (gradient/shift_mapping.h).
        l.visible = l.infinite ? escapes(scene_, v.si.endpoint(), ds.wi)
                               : unoccluded(scene_, v.si.endpoint(), {ds.p, ds.n, ds.magnitude});
    }

    std::optional<Spectrum> scattered(const SurfaceInteraction&, const WorldBsdf&, const BsdfSample& bs) {
        BaseVertex& v = path_.vertices.back();
        v.wo = bs.wo;
        v.lobe = bs.lobe;
        v.pdf = bs.pdf;
        // Non-delta values from eval(), as the shift evaluates its offsets (BaseVertex::scatter).
        v.fCos = v.delta() ? bs.weight * bs.pdf : v.scatter(v.wi, v.wo).fCos;
        if (v.fCos.isBlack() || !(v.pdf > 0)) return std::nullopt;
        return v.fCos / v.pdf;
    }

    void survived(double q) { path_.vertices.back().survival = q; }

private:
    const Scene& scene_;
    double shiftThreshold_;
    std::optional<BaseVertex> primary_;
    BasePath& path_;
};

} // namespace

BasePath traceBasePath(const Scene& scene, const PathSettings& settings, double shiftThreshold, const Vec2& raster,
                       const Vec3& lens, std::optional<BaseVertex> primary, SampleGenerator& sampler) {
    BasePath path;
    path.raster = raster;
    path.rrDepth = settings.rrDepth;
    const Ray ray = scene.camera.generateRay(raster, lens);
    std::optional<SurfaceInteraction> hit;
    if (primary) hit = primary->si;
    Record record(scene, shiftThreshold, std::move(primary), path);
    walkFromCamera(scene, settings, ray, hit, sampler, record);
    return path;
}

} // namespace lt
