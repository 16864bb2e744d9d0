#include "sampling/bdpt.h"

#include <algorithm>
#include <utility>

#include "bsdf/shading_correction.h"
#include "util/error.h"
#include "path/scatter.h"
#include "sampling/lens_sample.h"
#include "sampling/mis.h"

namespace lt {

namespace {

// Bound on subpath length when maxDepth is unbounded: Russian roulette ends paths long before it; the
// cap only guards memory against a pathological closed mirror box.
constexpr size_t UnboundedVertices = 1024;

double remap0(double x) { return x != 0 ? x : 1.0; }

// Restores what the MIS weight edits in place at scope exit (pbrt-v3's ScopedAssignment, to avoid
// copying subpaths per strategy): a whole vertex where the connection replaced a subpath's first one,
// only the reverse density and delta flag of the vertices around the connection.
class SavedVertex {
public:
    void save(PathVertex* v) {
        if (v) {
            target_ = v;
            saved_ = *v;
        }
    }
    ~SavedVertex() {
        if (target_) *target_ = saved_;
    }

private:
    PathVertex* target_ = nullptr;
    PathVertex saved_;
};

class SavedDensity {
public:
    void save(PathVertex* v) {
        if (v) {
            target_ = v;
            pdfRev_ = v->pdfRev;
            delta_ = v->delta;
        }
    }
    ~SavedDensity() {
        if (target_) {
            target_->pdfRev = pdfRev_;
            target_->delta = delta_;
        }
    }

private:
    PathVertex* target_ = nullptr;
    double pdfRev_ = 0;
    bool delta_ = false;
};

} // namespace

Bdpt::Bdpt(const Scene& scene, PathSettings settings) : scene_(scene), settings_(settings) {
    settings_.check();
    // A path of maxDepth edges has maxDepth + 1 vertices: the camera subpath may supply all but the light
    // vertex, the light subpath all but the camera vertex.
    maxCameraVertices_ = settings_.maxDepth < 0 ? UnboundedVertices : size_t(settings_.maxDepth) + 1;
    maxLightVertices_ = settings_.maxDepth < 0 ? UnboundedVertices : size_t(settings_.maxDepth);
}

void Bdpt::randomWalk(Ray ray, Spectrum beta, double pdfDir, SampleGenerator& sampler, Transport mode,
                      size_t maxVertices, std::vector<PathVertex>& path) const {
    double pdfFwd = pdfDir;
    const double startMax = beta.maxValue() > 0 ? beta.maxValue() : 1.0;
    double etaScale = 1;
    for (size_t added = 0; added < maxVertices;) {
        auto hit = traceVertex(scene_, ray);
        PathVertex& prev = path.back();
        if (!hit) {
            // An escaped camera path ends on the environment, if there is one (s = 0 strategies).
            if (mode == Transport::Radiance && !scene_.environmentEmitters.empty()) {
                PathVertex v = environmentVertex(scene_, ray.o, ray.d);
                v.beta = beta;
                v.pdfFwd = pdfFwd; // solid angle: an environment vertex has no area
                path.push_back(v);
            }
            return;
        }
        hit->wi = -ray.d;
        hit->beta = beta;
        hit->pdfFwd = prev.convertDensity(pdfFwd, *hit);
        path.push_back(std::move(*hit)); // `prev` may dangle from here on
        ++added;
        PathVertex& cur = path.back();
        if (added >= maxVertices || !cur.bsdf) return;
        const double uLobe = sampler.next1D();
        const Vec2 u = sampler.next2D();
        const auto bs = sampleScattering(cur, cur.wi, mode, uLobe, u);
        if (!bs) return;
        double pdfRev;
        if (cur.delta) {
            // A delta lobe cannot be reached by a connection: both densities are 0 (pbrt-v3 16.3.1).
            pdfFwd = pdfRev = 0;
        } else {
            pdfFwd = bs->pdf;
            pdfRev = cur.worldBsdf().pdf(bs->wo, cur.wi);
        }
        beta *= bs->weight;
        if (mode == Transport::Radiance && (bs->lobe & LobeTransmission)) etaScale *= bs->eta * bs->eta;
        // Russian roulette from rrDepth edges on, on the throughput relative to the subpath's start.
        const int edges = int(path.size()) - 1;
        if (edges >= settings_.rrDepth) {
            const double q = russianRouletteSurvival(beta / startMax, etaScale);
            if (!(sampler.next1D() < q)) return;
            beta /= q;
        }
        path[path.size() - 2].pdfRev = cur.convertDensity(pdfRev, path[path.size() - 2]);
        ray = rayFrom(cur, bs->wo);
    }
}

void Bdpt::cameraSubpath(const Vec2& raster, SampleGenerator& sampler, std::vector<PathVertex>& path,
                         size_t maxVertices) const {
    const size_t limit = maxVertices > 0 ? std::min(maxVertices, maxCameraVertices_) : maxCameraVertices_;
    path.clear();
    sampler.startStream(SampleGenerator::CameraStream);
    const PerspectiveCamera& camera = scene_.camera;
    const Vec3 lens = sampleLensPoint(camera, sampler);
    const Ray ray = camera.generateRay(raster, lens);
    PathVertex cam;
    cam.type = VertexType::Camera;
    cam.si.p = ray.o;
    // Raster positions are sampled from the pixel filter and credited to their pixel with weight 1:
    // W_e / p = 1 in the pixel measurement (film.h), so the camera vertex carries no factor.
    cam.beta = Spectrum(1.0);
    path.push_back(cam);
    double pdfPos = 0, pdfDir = 0;
    camera.pdfEmission(lens, ray.d, pdfPos, pdfDir);
    randomWalk(ray, Spectrum(1.0), pdfDir, sampler, Transport::Radiance, limit - 1, path);
}

void Bdpt::lightSubpath(SampleGenerator& sampler, std::vector<PathVertex>& path, size_t maxVertices) const {
    path.clear();
    sampler.startStream(SampleGenerator::LightStream);
    const size_t limit = maxVertices > 0 ? std::min(maxVertices, maxLightVertices_) : maxLightVertices_;
    if (scene_.emitterSelection.empty() || limit == 0) return;
    const double uLight = sampler.next1D();
    const Vec2 uPos = sampler.next2D(), uDir = sampler.next2D();
    const size_t index = scene_.emitterSelection.sample(uLight);
    const double pmf = scene_.emitterSelection.pmf(index);
    const Emitter& e = *scene_.emitters[index];
    const EmissionSample es = e.sampleEmission(uPos, uDir);
    if (!(es.pdfPos > 0) || !(es.pdfDir > 0) || es.value.isBlack()) return;

    PathVertex v = lightVertexAt(scene_, index, es.p, e.isInfinite() ? es.d : es.n, es.prim, es.coords);
    v.beta = es.value;
    v.pdfFwd = pmf * es.pdfPos;
    path.push_back(v);
    const double cosine = lengthSquared(es.n) > 0 && !v.infinite ? std::abs(dot(es.n, es.d)) : 1.0;
    const Spectrum beta = es.value * (cosine / (pmf * es.pdfPos * es.pdfDir));
    const Ray ray = v.isOnSurface() ? spawnRay(v.si.endpoint(), es.d) : Ray{es.p, es.d};
    // An environment vertex has no area: the next vertex's density is the disk's position density
    // (parallel rays: PathVertex::convertDensity), and the vertex's own is the density of its direction
    // (pbrt-v3 16.3.2).
    randomWalk(ray, beta, v.infinite ? es.pdfPos : es.pdfDir, sampler, Transport::Importance, limit - 1, path);
    if (v.infinite) path[0].pdfFwd = infiniteLightDensity(scene_, -es.d);
}

Spectrum Bdpt::connect(std::vector<PathVertex>& light, std::vector<PathVertex>& camera, int s, int t,
                       SampleGenerator& sampler, Vec2& raster, PathVertex& sampled, double& weight) const {
    weight = 0;
    Spectrum L;
    // A camera subpath that escaped to the environment ends there; nothing connects to it.
    if (t > 1 && s != 0 && camera[size_t(t) - 1].type == VertexType::Light) return {};
    if (s == 0) {
        const PathVertex& pt = camera[size_t(t) - 1];
        if (pt.isLight()) L = pt.Le(scene_, camera[size_t(t) - 2]) * pt.beta;
    } else if (t == 1) {
        // Light tracing: join the light subpath to a point of the lens (the pinhole, or a point uniform on
        // the aperture) and splat at the raster position it sees.
        const PathVertex& qs = light[size_t(s) - 1];
        if (!qs.isConnectible()) return {};
        const PerspectiveCamera& cam = scene_.camera;
        if (cam.hasAperture()) sampler.startStream(SampleGenerator::ConnectStream);
        const Vec3 lens = sampleLensPoint(cam, sampler);
        const Vec3 d = qs.si.p - lens;
        const double dist = length(d);
        const Vec3 dir = d / dist;
        const auto r = cam.rasterPosition(lens, dir);
        if (!r) return {};
        const double cosCam = dot(dir, cam.forward());
        const double We = cam.importance(lens, dir);
        // Camera rays start at the near clip plane; points before it are invisible to them and must be
        // to light tracing too.
        if (!(We > 0) || !(cosCam > 0) || dist * cosCam < cam.nearClip()) return {};
        sampled = PathVertex{};
        sampled.type = VertexType::Camera;
        sampled.si.p = lens;
        // The lens point as a direct sample from qs: area density 1 / A_lens on the lens, d^2 / (cos A_lens)
        // in solid angle at qs (pbrt-v3 PerspectiveCamera::Sample_Wi; a pinhole is a lens of area 1).
        sampled.beta = Spectrum(We * cosCam * cam.lensArea() / (dist * dist));
        L = qs.beta * qs.f(sampled, Transport::Importance) * sampled.beta;
        if (qs.isOnSurface()) L *= std::abs(dot(dir, qs.si.ng));
        if (!L.isBlack() && !visible(scene_, qs, sampled)) L = {};
        raster = *r;
    } else if (s == 1) {
        // Next-event estimation: a fresh point on a light, sampled toward the camera vertex.
        const PathVertex& pt = camera[size_t(t) - 1];
        if (!pt.isConnectible() || scene_.emitterSelection.empty()) return {};
        sampler.startStream(SampleGenerator::ConnectStream);
        const size_t index = scene_.emitterSelection.sample(sampler.next1D());
        const DirectSample ds = scene_.emitters[index]->sampleDirect(pt.si.p, sampler.next2D());
        if (!(ds.pdf > 0) || ds.value.isBlack()) return {};
        sampled = directLightVertex(scene_, index, ds);
        sampled.pdfFwd = sampled.pdfLightOrigin(scene_, pt);
        L = pt.beta * pt.f(sampled, Transport::Radiance) * sampled.beta;
        if (pt.isOnSurface()) L *= std::abs(dot(ds.wi, pt.si.ng));
        if (!L.isBlack() && !visible(scene_, pt, sampled)) L = {};
    } else {
        const PathVertex& qs = light[size_t(s) - 1];
        const PathVertex& pt = camera[size_t(t) - 1];
        if (!qs.isConnectible() || !pt.isConnectible()) return {};
        L = qs.beta * qs.f(pt, Transport::Importance) * pt.f(qs, Transport::Radiance) * pt.beta;
        if (!L.isBlack()) L *= geometryTerm(qs, pt);
        if (!L.isBlack() && !visible(scene_, qs, pt)) L = {};
    }
    if (L.isBlack()) return {};
    weight = misWeight(light, camera, sampled, s, t);
    return L;
}

double Bdpt::misWeight(std::vector<PathVertex>& light, std::vector<PathVertex>& camera, const PathVertex& sampled,
                       int s, int t) const {
    if (s + t == 2) return 1; // the only strategy lt uses for paths of one edge (emitters seen directly)
    // The connection's endpoints take the place of a subpath's first vertex when it was sampled anew.
    SavedVertex savedLight0, savedCamera0;
    if (s == 1) {
        savedLight0.save(&light[0]);
        light[0] = sampled;
    }
    if (t == 1) {
        savedCamera0.save(&camera[0]);
        camera[0] = sampled;
    }
    PathVertex* qs = s > 0 ? &light[size_t(s) - 1] : nullptr;
    PathVertex* pt = &camera[size_t(t) - 1];
    PathVertex* qsMinus = s > 1 ? &light[size_t(s) - 2] : nullptr;
    PathVertex* ptMinus = t > 1 ? &camera[size_t(t) - 2] : nullptr;
    // Saved after the replacements above and so restored before them (reverse order of destruction):
    // the subpaths end exactly as they were.
    SavedDensity a, b, c, d;
    a.save(pt);
    b.save(qs);
    c.save(ptMinus);
    d.save(qsMinus);

    // The joined vertices are reached by a connection, never through a delta lobe.
    pt->delta = false;
    if (qs) qs->delta = false;
    // Reverse densities of the four vertices around the connection (Veach thesis 10.2; pbrt-v3 MISWeight).
    pt->pdfRev = s > 0 ? qs->pdf(scene_, qsMinus, *pt) : pt->pdfLightOrigin(scene_, *ptMinus);
    if (ptMinus) ptMinus->pdfRev = s > 0 ? pt->pdf(scene_, qs, *ptMinus) : pt->pdfLight(scene_, *ptMinus);
    if (qs) qs->pdfRev = pt->pdf(scene_, ptMinus, *qs);
    if (qsMinus) qsMinus->pdfRev = qs->pdf(scene_, pt, *qsMinus);

    // Ratios p_i / p_s of the other strategies' densities, walking away from the connection on both
    // sides; strategies that would connect through a delta vertex do not exist.
    double sum = 0, r = 1;
    for (int i = t - 1; i > 0; --i) {
        r *= remap0(camera[size_t(i)].pdfRev) / remap0(camera[size_t(i)].pdfFwd);
        if (!camera[size_t(i)].delta && !camera[size_t(i) - 1].delta) sum += misHeuristic(settings_.mis, r);
    }
    r = 1;
    for (int i = s - 1; i >= 0; --i) {
        r *= remap0(light[size_t(i)].pdfRev) / remap0(light[size_t(i)].pdfFwd);
        const bool deltaBefore = i > 0 ? light[size_t(i) - 1].delta : light[0].isDeltaLight();
        if (!light[size_t(i)].delta && !deltaBefore) sum += misHeuristic(settings_.mis, r);
    }
    return 1.0 / (1.0 + sum);
}

Spectrum Bdpt::strategy(std::vector<PathVertex>& light, std::vector<PathVertex>& camera, int s, int t,
                        SampleGenerator& sampler, Vec2& raster) const {
    PathVertex sampled;
    double weight = 0;
    const Spectrum c = connect(light, camera, s, t, sampler, raster, sampled, weight);
    return c.isBlack() ? c : c * weight;
}

Spectrum Bdpt::sample(const Vec2& raster, SampleGenerator& sampler, std::vector<Splat>& splats, SampleHealth& health,
                      const StrategyCallback* onPath) const {
    thread_local std::vector<PathVertex> camera, light;
    cameraSubpath(raster, sampler, camera);
    lightSubpath(sampler, light);
    Spectrum L;
    for (int t = 1; t <= int(camera.size()); ++t) {
        for (int s = 0; s <= int(light.size()); ++s) {
            const int edges = s + t - 1;
            if (edges < 1 || (s == 1 && t == 1)) continue;
            if (edges < settings_.minDepth || (settings_.maxDepth >= 0 && edges > settings_.maxDepth)) continue;
            const bool single = settings_.onlyS >= 0;
            if (single && (s != settings_.onlyS || t != settings_.onlyT)) continue;
            Vec2 splatRaster;
            PathVertex sampled;
            double weight = 0;
            const Spectrum c = connect(light, camera, s, t, sampler, splatRaster, sampled, weight);
            if (c.isBlack()) continue;
            const Spectrum value = single ? c : c * weight;
            if (!value.isFinite()) {
                ++health.nonFinite;
                continue;
            }
            if (t == 1)
                splats.push_back({splatRaster, value});
            else
                L += value;
            if (onPath) {
                StrategyPath sp;
                sp.s = s;
                sp.t = t;
                sp.light = &light;
                sp.camera = &camera;
                sp.sampled = (s == 1 || t == 1) ? &sampled : nullptr;
                sp.raster = t == 1 ? splatRaster : raster;
                sp.unweighted = c;
                sp.misWeight = single ? 1.0 : weight;
                (*onPath)(sp);
            }
        }
    }
    return L;
}

const EstimatorKind Bdpt::Kind{
    "bdpt",
    "bidirectional path tracing: every (s,t) strategy, light tracing included, weighted by MIS",
    {misOption()},
    {},
    [](const Scene& scene, const PathSettings& paths, const OptionValues& values) -> std::unique_ptr<PixelEstimator> {
        return std::make_unique<Bdpt>(scene, withMis(paths, values));
    },
    {}};

} // namespace lt
