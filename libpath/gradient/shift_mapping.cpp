#include "gradient/shift_mapping.h"

#include "bsdf/half_vector.h"
#include "path/vertex.h"
#include "scene/measure.h"
#include "scene/scene.h"

namespace lt {

namespace {

// Radiance that the emitter on surface vertex z sends along `d` (leaving z), and the density with which a
// light sample from `ref` picks that point (solid angle).
Spectrum surfaceRadiance(const Scene& scene, const BaseVertex& z, const Vec3& d) {
    return z.emitter >= 0 ? scene.emitters[size_t(z.emitter)]->evalSurface(z.si.p, z.si.ng, d) : Spectrum();
}

double surfaceLightPdf(const Scene& scene, const Vec3& ref, const BaseVertex& z, const Vec3& dir) {
    if (z.emitter < 0) return 0;
    const Emitter& em = *scene.emitters[size_t(z.emitter)];
    if (em.isDelta()) return 0;
    return scene.emitterSelection.pmf(size_t(z.emitter)) * em.pdfDirect(ref, z.si.p, z.si.ng, dir);
}

// The light sample's value and density seen from another vertex at `ref` (the same point on the light).
struct LightSeen {
    Vec3 wo;
    Spectrum Le;
    double pdfLight = 0;
    double jacobian = 1; // solid angle at the offset over solid angle at the base vertex
};

LightSeen lightSeenFrom(const Scene& scene, const BaseLightSample& l, const Vec3& ref, const Vec3& base) {
    LightSeen s;
    const Emitter& em = *scene.emitters[size_t(l.emitter)];
    const double pmf = scene.emitterSelection.pmf(size_t(l.emitter));
    if (l.infinite) {
        s.wo = l.wo;
        s.Le = l.delta ? l.Le : environmentRadiance(scene, l.wo);
        s.pdfLight = l.delta ? l.pdfLight : environmentPdf(scene, ref, l.wo);
        return s;
    }
    const Vec3 v = l.p - ref;
    const double d2 = lengthSquared(v);
    s.wo = v / std::sqrt(d2);
    if (l.delta) { // point and spot lights: the same point, a counting measure
        s.Le = em.intensity(-s.wo) / d2;
        s.pdfLight = l.pdfLight;
        return s;
    }
    s.Le = em.evalSurface(l.p, l.n, -s.wo);
    s.pdfLight = pmf * em.pdfDirect(ref, l.p, l.n, s.wo);
    s.jacobian = pdfSolidAngleToArea(1, ref, l.p, l.n) / pdfSolidAngleToArea(1, base, l.p, l.n);
    return s;
}

// f_s |cos| and the BSDF density of vertex v from its incident direction wi toward wo.
struct Scatter {
    Spectrum fCos;
    double pdf = 0;
};

Scatter scatterToward(const BaseVertex& v, const Vec3& wi, const Vec3& wo) {
    const WorldBsdf wb = v.worldBsdf();
    return {wb.eval(wi, wo, Transport::Radiance) * std::abs(dot(wo, v.si.ng)), wb.pdf(wi, wo)};
}

} // namespace

std::optional<HalfVectorCopy> copyHalfVector(const BaseVertex& x, const Vec3& wiX, const Vec3& woX, bool deltaLobe,
                                             const BaseVertex& y) {
    const Vec3 wiXl = x.si.shading.toLocal(wiX), woXl = x.si.shading.toLocal(woX);
    const Vec3 wiYl = y.si.shading.toLocal(y.wi);
    if ((wiXl.z > 0) != (wiYl.z > 0)) return std::nullopt;
    const bool transmit = wiXl.z * woXl.z < 0;
    double etaX = 1, etaY = 1;
    if (transmit) {
        const auto ex = x.bsdf->eta(), ey = y.bsdf->eta();
        if (!ex || !ey) return std::nullopt;
        // eta = eta_o / eta_i: the index of the side entered over that of the incident side.
        etaX = wiXl.z > 0 ? ex->interior / ex->exterior : ex->exterior / ex->interior;
        etaY = wiYl.z > 0 ? ey->interior / ey->exterior : ey->exterior / ey->interior;
    }
    const auto h = halfVector(wiXl, woXl, etaX);
    if (!h) return std::nullopt;
    Vec3 woYl;
    if (!transmit) {
        woYl = 2 * dot(wiYl, *h) * *h - wiYl;
        if (!(woYl.z * wiYl.z > 0)) return std::nullopt;
    } else {
        const auto t = refract(wiYl, *h, etaY);
        if (!t || !(t->z * wiYl.z < 0)) return std::nullopt;
        woYl = *t;
    }
    HalfVectorCopy f;
    f.wo = normalize(y.si.shading.toWorld(woYl));
    if (deltaLobe) {
        const auto ds = y.worldBsdf().deltaEval(y.wi, f.wo, Transport::Radiance);
        if (!ds || !(ds->pdf > 0)) return std::nullopt;
        f.fCos = ds->weight * ds->pdf;
        f.pdf = ds->pdf;
        return f;
    }
    const Scatter s = scatterToward(y, y.wi, f.wo);
    f.fCos = s.fCos;
    f.pdf = s.pdf;
    const double jx = halfVectorJacobian(*h, wiXl, woXl, etaX), jy = halfVectorJacobian(*h, wiYl, woYl, etaY);
    if (!(jx > 0) || !(jy > 0)) return std::nullopt;
    f.jacobian = jx / jy;
    return f;
}

namespace {

// The ending reached by tracing from y along wo (the following branch): emitter or environment radiance and
// the light-sample density of that point from y.
struct Reached {
    Spectrum Le;
    double pdfLight = 0;
};

Reached reachedFrom(const Scene& scene, const Vec3& from, const BaseVertex* hit, const Vec3& wo, bool deltaLobe) {
    Reached r;
    if (hit) {
        r.Le = surfaceRadiance(scene, *hit, -wo);
        if (!deltaLobe) r.pdfLight = surfaceLightPdf(scene, from, *hit, wo);
    } else {
        r.Le = environmentRadiance(scene, wo);
        if (!deltaLobe) r.pdfLight = environmentPdf(scene, from, wo);
    }
    return r;
}

std::optional<BaseVertex> traceFrom(const Scene& scene, const BaseVertex& y, const Vec3& wo) {
    auto hit = scene.intersect(spawnRay(y.si.endpoint(), wo));
    if (!hit) return std::nullopt;
    BaseVertex v;
    v.si = std::move(*hit);
    v.bsdf = scene.bsdfOf(v.si);
    v.emitter = scene.shapes[size_t(v.si.shape)].emitter;
    v.wi = -wo;
    return v;
}

// Radiance reaching x_i along its BSDF sample (ending 2i + 1), and the light-sample density of it from x_i.
Reached baseReached(const Scene& scene, const BasePath& base, size_t i) {
    const BaseVertex& x = base.vertices[i];
    return reachedFrom(scene, x.si.p, x.escaped ? nullptr : &base.vertices[i + 1], x.wo, x.delta());
}

// The eta^2 a transmission from wi to wo at v multiplies Russian roulette's etaScale by (1 for reflection).
double etaSquared(const BaseVertex& v, const Vec3& wi, const Vec3& wo) {
    if (dot(wi, v.si.ng) * dot(wo, v.si.ng) >= 0) return 1;
    const auto e = v.bsdf->eta();
    if (!e) return 1;
    const double eta = dot(wo, v.si.ng) < 0 ? e->interior / e->exterior : e->exterior / e->interior;
    return eta * eta;
}

// A technique's prefix: the path so far as pixel m's path tracer would have sampled it. value and density
// are f_m |T'| and p_m |T'| over the base path's own (actual) density; beta and etaScale are pixel m's own
// throughput and refraction factor, from which its Russian roulette decides (sampling/path_settings.h).
// Densities include Russian roulette and stop where a path tracer stops (a black BSDF sample), so that every
// density in a weight is that of a technique that can produce the path (Kettunen et al. 2015, Sec. 6.2).
struct Prefix {
    Spectrum value{1.0};
    double density = 1;
    Spectrum beta{1.0};
    double etaScale = 1;

    // Russian roulette's survival probability after a BSDF sample with these factors at the vertex of
    // `edges` edges (1 at the primary hit); 0 where the path tracer would stop.
    [[nodiscard]] double survival(const Spectrum& fCos, double pdf, double eta2, int edges, int rrDepth) const {
        if (fCos.isBlack() || !(pdf > 0)) return 0;
        return edges >= rrDepth ? russianRouletteSurvival(beta * fCos / pdf, etaScale * eta2) : 1.0;
    }
};

// The terms of ending 2j, the light sample at x_j, for a technique that reaches x_j from direction wi with
// `prefix`; light seen as `light` (the base's, or the same point from an offset vertex). The BSDF sample
// reaches the light point only when the shadow ray is free.
EndingTerm lightEnding(const BaseVertex& x, const Vec3& wi, const Prefix& prefix, const LightSeen& light, bool free,
                       double baseLightPdf, int edges, int rrDepth) {
    const Scatter s = scatterToward(x, wi, light.wo);
    const double q = prefix.survival(s.fCos, s.pdf, etaSquared(x, wi, light.wo), edges, rrDepth);
    const double pdfBsdf = x.light.delta || !free ? 0.0 : q * s.pdf;
    return {free ? prefix.value * s.fCos * light.Le * (light.jacobian / baseLightPdf) : Spectrum(),
            prefix.density * (light.pdfLight + pdfBsdf) * light.jacobian / baseLightPdf};
}

LightSeen baseLight(const BaseLightSample& l) { return {l.wo, l.Le, l.pdfLight, 1.0}; }

// The step of a technique's prefix through vertex x_i of the base path (x: the base vertex, whose sampled
// direction had density x.pdf x.survival), with the technique's own factors there and the Jacobian.
void step(Prefix& p, const BaseVertex& x, const Spectrum& fCos, double pdf, double q, double eta2, double jacobian) {
    p.value *= fCos * (jacobian / (x.pdf * x.survival));
    p.density *= q * pdf * jacobian / (x.pdf * x.survival);
    if (q > 0) {
        p.beta *= fCos / (pdf * q);
        p.etaScale *= eta2;
    }
}

// The terms of the BSDF ending leaving x_i: the prefix before x_i, the technique's factors there, and what
// the direction reaches (radiance, light-sample density), `free` when the technique's ray gets there.
EndingTerm bsdfEnding(const Prefix& before, const BaseVertex& x, const Spectrum& fCos, double pdf, double q,
                      double jacobian, const Reached& r, bool free) {
    return {free ? before.value * fCos * r.Le * (jacobian / (x.pdf * x.survival)) : Spectrum(),
            before.density * ((free ? q * pdf : 0.0) + r.pdfLight) * jacobian / (x.pdf * x.survival)};
}

struct Shifter {
    const Scene& scene;
    const BasePath& base;
    double threshold;
    std::vector<EndingTerm>& out;

    // The endings from x_j on for an offset that joined the base path by reaching x_j from direction wi.
    // No ray is traced: visibility is the base path's.
    void tail(size_t j, const Vec3& wi, Prefix p) {
        for (size_t k = j; k < base.vertices.size(); ++k) {
            const BaseVertex& x = base.vertices[k];
            const Vec3& in = k == j ? wi : x.wi;
            const int edges = int(k) + 1;
            if (x.light.emitter >= 0)
                out[2 * k] =
                    lightEnding(x, in, p, baseLight(x.light), x.light.visible, x.light.pdfLight, edges, base.rrDepth);
            if (!x.scattered) return;
            const Scatter s = k == j ? scatterToward(x, in, x.wo) : Scatter{x.fCos, x.pdf};
            const double eta2 = etaSquared(x, in, x.wo);
            const double q = p.survival(s.fCos, s.pdf, eta2, edges, base.rrDepth);
            out[2 * k + 1] = bsdfEnding(p, x, s.fCos, s.pdf, q, 1, baseReached(scene, base, k), true);
            step(p, x, s.fCos, s.pdf, q, eta2, 1);
        }
    }

    // Ending 2i, the light sample at x_i, for the offset at y.
    void shiftLightSample(const BaseVertex& x, size_t i, const BaseVertex& y, const Prefix& p) {
        const BaseLightSample& l = x.light;
        if (connectableLobe(*y.bsdf, y.si.uv, false, threshold) != x.connectable) return;
        const int edges = int(i) + 1;
        if (x.connectable) { // reconnect to the same point on the light
            const LightSeen s = lightSeenFrom(scene, l, y.si.p, x.si.p);
            const bool free = l.infinite ? escapes(scene, y.si.endpoint(), s.wo)
                                         : unoccluded(scene, y.si.endpoint(), {l.p, l.n, l.magnitude});
            out[2 * i] = lightEnding(y, y.wi, p, s, free, l.pdfLight, edges, base.rrDepth);
        } else if (const auto f = copyHalfVector(x, x.wi, l.wo, false, y)) {
            const auto hit = traceFrom(scene, y, f->wo);
            const Reached r = reachedFrom(scene, y.si.p, hit ? &*hit : nullptr, f->wo, false);
            const double q = p.survival(f->fCos, f->pdf, etaSquared(y, y.wi, f->wo), edges, base.rrDepth);
            out[2 * i] = {p.value * f->fCos * r.Le * (f->jacobian / l.pdfLight),
                          p.density * (r.pdfLight + q * f->pdf) * f->jacobian / l.pdfLight};
        }
    }

    ShiftOutcome run(const std::optional<BaseVertex>& offset) {
        const size_t n = base.vertices.size();
        out.assign(2 * n, {});
        if (n == 0) return {ShiftCause::Followed};
        if (!offset) return {ShiftCause::NoPrimaryHit};
        BaseVertex y = *offset;
        Prefix p;
        for (size_t i = 0; i < n; ++i) {
            const BaseVertex& x = base.vertices[i];
            const int edges = int(i) + 1;
            if (!x.bsdf) return {ShiftCause::Followed};
            if (!y.bsdf) return {ShiftCause::Mismatch};
            if (x.light.emitter >= 0) shiftLightSample(x, i, y, p);

            // Ending 2i + 1 and the path beyond it.
            if (!x.scattered) return {ShiftCause::Followed};
            const bool connectable = connectableLobe(*x.bsdf, x.si.uv, x.delta(), threshold);
            if (connectableLobe(*y.bsdf, y.si.uv, x.delta(), threshold) != connectable) return {ShiftCause::Mismatch};
            const BaseVertex* next = x.escaped ? nullptr : &base.vertices[i + 1];
            if (connectable) {
                // Reconnect y_i to x_{i+1} (or send it along the same direction to the environment).
                Vec3 wo = x.wo;
                double jacobian = 1;
                bool free;
                if (next) {
                    wo = normalize(next->si.p - y.si.p);
                    jacobian = pdfSolidAngleToArea(1, y.si.p, next->si.p, next->si.ng) /
                               pdfSolidAngleToArea(1, x.si.p, next->si.p, next->si.ng);
                    free = unoccluded(scene, y.si.endpoint(), next->si.endpoint());
                } else {
                    free = escapes(scene, y.si.endpoint(), wo);
                }
                const Scatter s = scatterToward(y, y.wi, wo);
                const double eta2 = etaSquared(y, y.wi, wo);
                const double q = p.survival(s.fCos, s.pdf, eta2, edges, base.rrDepth);
                // Blocked, the path is still a light sample's (when x_{i+1} emits), not a BSDF sample's.
                out[2 * i + 1] =
                    bsdfEnding(p, x, s.fCos, s.pdf, q, jacobian, reachedFrom(scene, y.si.p, next, wo, false), free);
                if (!free) return {ShiftCause::Occluded};
                if (!next) return {ShiftCause::Reconnected, edges};
                Prefix joined = p;
                step(joined, x, s.fCos, s.pdf, q, eta2, jacobian);
                // x_{i+1} is a reconnection target for the endings that leave it through a non-delta lobe.
                if (next->connectable && !(next->scattered && next->delta())) {
                    tail(i + 1, -wo, joined);
                    return {ShiftCause::Reconnected, edges};
                }
                // x_{i+1} took a delta lobe: only its light sample joins here; the rest follows half vectors.
                if (next->connectable && next->light.emitter >= 0)
                    out[2 * i + 2] = lightEnding(*next, -wo, joined, baseLight(next->light), next->light.visible,
                                                 next->light.pdfLight, edges + 1, base.rrDepth);
                // Nothing leaves x_{i+1} (the path ends there): no ending is left to follow.
                if (!next->scattered && next->light.emitter < 0) return {ShiftCause::Reconnected, edges};
            }
            const auto f = copyHalfVector(x, x.wi, x.wo, x.delta(), y);
            if (!f) return {ShiftCause::Refraction};
            auto hit = traceFrom(scene, y, f->wo);
            const double eta2 = etaSquared(y, y.wi, f->wo);
            const double q = p.survival(f->fCos, f->pdf, eta2, edges, base.rrDepth);
            if (!connectable)
                out[2 * i + 1] = bsdfEnding(p, x, f->fCos, f->pdf, q, f->jacobian,
                                            reachedFrom(scene, y.si.p, hit ? &*hit : nullptr, f->wo, x.delta()), true);
            step(p, x, f->fCos, f->pdf, q, eta2, f->jacobian);
            if (!next) return {ShiftCause::Followed};
            if (!hit) return {ShiftCause::Escaped};
            y = std::move(*hit);
        }
        return {ShiftCause::Followed};
    }
};

} // namespace

std::vector<EndingTerm> baseEndingTerms(const Scene& scene, const BasePath& base) {
    const size_t n = base.vertices.size();
    std::vector<EndingTerm> terms(2 * n);
    Prefix p;
    for (size_t i = 0; i < n; ++i) {
        const BaseVertex& x = base.vertices[i];
        const int edges = int(i) + 1;
        if (x.light.emitter >= 0)
            terms[2 * i] =
                lightEnding(x, x.wi, p, baseLight(x.light), x.light.visible, x.light.pdfLight, edges, base.rrDepth);
        if (!x.scattered) break;
        const double eta2 = etaSquared(x, x.wi, x.wo);
        terms[2 * i + 1] = bsdfEnding(p, x, x.fCos, x.pdf, x.survival, 1, baseReached(scene, base, i), true);
        step(p, x, x.fCos, x.pdf, x.survival, eta2, 1);
    }
    return terms;
}

ShiftOutcome shiftBasePath(const Scene& scene, const BasePath& base, const std::optional<BaseVertex>& offset,
                           double shiftThreshold, std::vector<EndingTerm>& out) {
    return Shifter{scene, base, shiftThreshold, out}.run(offset);
}

bool shareOverPixels(const std::vector<const std::vector<EndingTerm>*>& terms, std::vector<Spectrum>& share) {
    const size_t pixels = terms.size(), endings = terms.empty() ? 0 : terms[0]->size();
    std::vector<Spectrum> add(pixels);
    for (size_t e = 0; e < endings; ++e) {
        double density = 0;
        bool carries = false;
        for (const auto* t : terms) {
            density += (*t)[e].density;
            carries = carries || !(*t)[e].value.isBlack();
        }
        if (!carries) continue;
        for (size_t m = 0; m < pixels; ++m)
            if (!(*terms[m])[e].value.isBlack()) add[m] += (*terms[m])[e].value / density;
    }
    for (const auto& a : add)
        if (!a.isFinite()) return false;
    for (size_t m = 0; m < pixels; ++m)
        share[m] += add[m];
    return true;
}

} // namespace lt
