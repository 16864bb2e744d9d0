#include "gradient/shift_mapping.h"

#include "bsdf/half_vector.h"
#include "path/vertex.h"
#include "scene/measure.h"
#include "scene/scene.h"

namespace lt {

double reconnectionJacobian(const Vec3& offset, const Vec3& base, const Vec3& z, const Vec3& n) {
    const double denom = pdfSolidAngleToArea(1, base, z, n);
    if (!(denom > 0)) return 0;
    const double j = pdfSolidAngleToArea(1, offset, z, n) / denom;
    return std::isfinite(j) ? j : 0.0;
}

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

// The light sample seen from the offset vertex at `ref` (the same point on the light); nothing when ref lies
// on that point.
std::optional<LightSeen> lightSeenFrom(const Scene& scene, const BaseLightSample& l, const Vec3& ref,
                                       const Vec3& base) {
    LightSeen s;
    const Emitter& em = *scene.emitters[size_t(l.emitter)];
    if (l.infinite) {
        s.wo = l.wo;
        s.Le = l.delta ? l.Le : environmentRadiance(scene, l.wo);
        s.pdfLight = l.delta ? l.pdfLight : environmentPdf(scene, ref, l.wo);
        return s;
    }
    const Vec3 v = l.p - ref;
    const double d2 = lengthSquared(v);
    if (!(d2 > 0)) return std::nullopt;
    s.wo = v / std::sqrt(d2);
    if (l.delta) { // point and spot lights: the same point, a counting measure
        s.Le = em.intensity(-s.wo) / d2;
        s.pdfLight = l.pdfLight;
        return s;
    }
    s.Le = em.evalSurface(l.p, l.n, -s.wo);
    s.pdfLight = scene.emitterSelection.pmf(size_t(l.emitter)) * em.pdfDirect(ref, l.p, l.n, s.wo);
    s.jacobian = reconnectionJacobian(ref, base, l.p, l.n);
    return s;
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
    HalfVectorCopy f;
    if (deltaLobe) {
        // A delta lobe's half vector is the shading normal: mirror, refract, or pass straight through a thin
        // sheet (eta 1), and let deltaEval confirm the lobe; the Jacobian is 1.
        Vec3 woYl = Vec3(-wiYl.x, -wiYl.y, wiYl.z);
        if (transmit) {
            if (etaY == 1) {
                woYl = -wiYl;
            } else {
                const auto t = refract(wiYl, Vec3(0, 0, 1), etaY);
                if (!t) return std::nullopt;
                woYl = *t;
            }
        }
        f.wo = normalize(y.si.shading.toWorld(woYl));
        const auto ds = y.worldBsdf().deltaEval(y.wi, f.wo, Transport::Radiance);
        if (!ds || !(ds->pdf > 0)) return std::nullopt;
        f.fCos = ds->weight * ds->pdf;
        f.pdf = ds->pdf;
        return f;
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
    f.wo = normalize(y.si.shading.toWorld(woYl));
    const VertexScatter s = y.scatter(y.wi, f.wo);
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

// The eta^2 a transmission from wi to wo at v multiplies Russian roulette's etaScale by (1 for reflection):
// BsdfSample::eta's, sides taken by the shading normal as the BSDFs take them.
double etaSquared(const BaseVertex& v, const Vec3& wi, const Vec3& wo) {
    const Vec3& n = v.si.shading.n;
    if (dot(wi, n) * dot(wo, n) >= 0) return 1;
    const auto e = v.bsdf->eta();
    if (!e) return 1;
    const double eta = dot(wo, n) < 0 ? e->interior / e->exterior : e->exterior / e->interior;
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
// `prefix`; light seen as `light` (the base's, or the same point from an offset vertex) of the base's light
// sample `sample`. The BSDF sample reaches the light point only when the shadow ray is free, and never a delta
// light.
EndingTerm lightEnding(const BaseVertex& x, const Vec3& wi, const Prefix& prefix, const LightSeen& light, bool free,
                       const BaseLightSample& sample, int edges, int rrDepth) {
    const VertexScatter s = x.scatter(wi, light.wo);
    const double q = prefix.survival(s.fCos, s.pdf, etaSquared(x, wi, light.wo), edges, rrDepth);
    const double pdfBsdf = sample.delta || !free ? 0.0 : q * s.pdf;
    const double baseLightPdf = sample.pdfLight;
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

    // The vertex where a shift may stop early (shift_mapping.h EarlyOut): the first reconnection vertex x_i
    // when nothing after x_i's light sample can carry light; the path's length otherwise. The same rules as
    // run() decide where a shift rejoins the base path.
    [[nodiscard]] size_t darkTailVertex() const {
        const size_t n = base.vertices.size();
        size_t i = 0;
        for (; i < n; ++i) {
            const BaseVertex& x = base.vertices[i];
            if (!x.bsdf || !x.scattered) return n;
            if (!connectableLobe(*x.bsdf, x.si.uv, x.delta(), threshold)) continue;
            if (x.escaped) break;
            const BaseVertex& next = base.vertices[i + 1];
            if (next.connectable && !(next.scattered && next.delta())) break;
        }
        for (size_t k = i; k < n; ++k) {
            const BaseVertex& x = base.vertices[k];
            if (k > i && x.light.emitter >= 0 && x.light.visible && !x.light.Le.isBlack()) return n;
            if (!x.scattered) break;
            if (x.escaped ? !environmentRadiance(scene, x.wo).isBlack() : base.vertices[k + 1].emitter >= 0) return n;
        }
        return i;
    }

    // The endings from x_j on for an offset that joined the base path by reaching x_j from direction wi.
    // No ray is traced: visibility is the base path's.
    void tail(size_t j, const Vec3& wi, Prefix p) {
        for (size_t k = j; k < base.vertices.size(); ++k) {
            const BaseVertex& x = base.vertices[k];
            const Vec3& in = k == j ? wi : x.wi;
            const int edges = int(k) + 1;
            if (x.light.emitter >= 0)
                out[2 * k] = lightEnding(x, in, p, baseLight(x.light), x.light.visible, x.light, edges, base.rrDepth);
            if (!x.scattered) return;
            const VertexScatter s = k == j ? x.scatter(in, x.wo) : VertexScatter{x.fCos, x.pdf};
            const double eta2 = etaSquared(x, in, x.wo);
            const double q = p.survival(s.fCos, s.pdf, eta2, edges, base.rrDepth);
            out[2 * k + 1] = bsdfEnding(p, x, s.fCos, s.pdf, q, 1, baseReached(scene, base, k), true);
            step(p, x, s.fCos, s.pdf, q, eta2, 1);
        }
    }

    // Ending 2i, the light sample at x_i, for the offset at y: its last segment always reconnects to the same
    // point on the light (as the public G-PT code does), whatever the roughness; the same rule ends the BSDF
    // sample's ending 2i + 1 through a non-delta lobe, so a path reaching a light is shifted alike by either
    // technique. An offset vertex without a non-delta lobe takes no light sample: no technique.
    void shiftLightSample(const BaseVertex& x, size_t i, const BaseVertex& y, const Prefix& p) {
        const BaseLightSample& l = x.light;
        if (!samplesLights(*y.bsdf)) return;
        const auto s = lightSeenFrom(scene, l, y.si.p, x.si.p);
        if (!s) return;
        const bool free = l.infinite ? escapes(scene, y.si.endpoint(), s->wo)
                                     : unoccluded(scene, y.si.endpoint(), {l.p, l.n, l.magnitude});
        out[2 * i] = lightEnding(y, y.wi, p, *s, free, l, int(i) + 1, base.rrDepth);
    }

    // The reconnection of y_i to x_{i+1} (or, when the base path left the scene there, the same direction
    // out of it), with y's factors for that direction.
    struct Join {
        Vec3 wo;
        double jacobian = 1;
        bool free = false;
        VertexScatter s;
        double eta2 = 1;
        double q = 0;
    };
    Join join(const BaseVertex& x, const BaseVertex* next, const BaseVertex& y, const Prefix& p, int edges) {
        Join j;
        j.wo = x.wo;
        if (next) {
            j.wo = normalize(next->si.p - y.si.p);
            j.jacobian = reconnectionJacobian(y.si.p, x.si.p, next->si.p, next->si.ng);
            j.free = j.jacobian > 0 && unoccluded(scene, y.si.endpoint(), next->si.endpoint());
        } else {
            j.free = escapes(scene, y.si.endpoint(), j.wo);
        }
        j.s = y.scatter(y.wi, j.wo);
        j.eta2 = etaSquared(y, y.wi, j.wo);
        j.q = p.survival(j.s.fCos, j.s.pdf, j.eta2, edges, base.rrDepth);
        return j;
    }

    ShiftOutcome run(const std::optional<BaseVertex>& offset, EarlyOut earlyOut) {
        const size_t n = base.vertices.size();
        out.assign(2 * n, {});
        if (n == 0) return {ShiftCause::Followed};
        if (!offset) return {ShiftCause::NoPrimaryHit};
        const size_t stop = earlyOut == EarlyOut::Take ? darkTailVertex() : n;
        BaseVertex y = *offset;
        Prefix p;
        size_t lightTaken = n; // a light ending already shifted by a reconnection one vertex earlier
        for (size_t i = 0; i < n; ++i) {
            const BaseVertex& x = base.vertices[i];
            const int edges = int(i) + 1;
            if (!x.bsdf) return {ShiftCause::Followed};
            if (!y.bsdf) return {ShiftCause::Mismatch};
            if (x.light.emitter >= 0 && i != lightTaken) shiftLightSample(x, i, y, p);
            if (!x.scattered) return {ShiftCause::Followed};
            const bool connectable = connectableLobe(*x.bsdf, x.si.uv, x.delta(), threshold);
            const bool alike = connectableLobe(*y.bsdf, y.si.uv, x.delta(), threshold) == connectable;
            // At the early out's vertex (connectable, so non-delta) the causes a full shift would give.
            if (i == stop)
                return {alike && samplesLights(*y.bsdf) ? ShiftCause::EarlyOut : ShiftCause::Mismatch, edges};
            const BaseVertex* next = x.escaped ? nullptr : &base.vertices[i + 1];

            // Ending 2i + 1 through a non-delta lobe ends by a reconnection, as the light sample does, whatever
            // the classification of y_i.
            std::optional<Join> joined;
            if (!x.delta()) {
                if (!samplesLights(*y.bsdf)) return {ShiftCause::Mismatch};
                joined = join(x, next, y, p, edges);
                // Blocked, the path is still a light sample's (when x_{i+1} emits), not a BSDF sample's.
                out[2 * i + 1] = bsdfEnding(p, x, joined->s.fCos, joined->s.pdf, joined->q, joined->jacobian,
                                            reachedFrom(scene, y.si.p, next, joined->wo, false), joined->free);
            }
            if (!alike) return {ShiftCause::Mismatch};
            if (connectable) {
                // x_i and y_i are connectable: the endings through x_{i+1} reconnect here when x_{i+1} is
                // connectable for them (all its endings, unless it took a delta lobe: then its light sample only).
                if (!next) return {joined->free ? ShiftCause::Reconnected : ShiftCause::Occluded, edges};
                const bool joins = next->connectable && !(next->scattered && next->delta());
                if (joined->free) {
                    Prefix jp = p;
                    step(jp, x, joined->s.fCos, joined->s.pdf, joined->q, joined->eta2, joined->jacobian);
                    if (joins) {
                        tail(i + 1, -joined->wo, jp);
                        return {ShiftCause::Reconnected, edges};
                    }
                    if (next->connectable && next->light.emitter >= 0)
                        out[2 * i + 2] = lightEnding(*next, -joined->wo, jp, baseLight(next->light),
                                                     next->light.visible, next->light, edges + 1, base.rrDepth);
                } else if (joins) {
                    return {ShiftCause::Occluded};
                }
                if (next->connectable) lightTaken = i + 1; // (blocked: no technique produces it)
                if (!next->scattered) return {ShiftCause::Reconnected, edges};
            }
            // Half-vector copy for the rest.
            const auto f = copyHalfVector(x, x.wi, x.wo, x.delta(), y);
            if (!f) return {ShiftCause::Refraction};
            auto hit = traceFrom(scene, y, f->wo);
            const double eta2 = etaSquared(y, y.wi, f->wo);
            const double q = p.survival(f->fCos, f->pdf, eta2, edges, base.rrDepth);
            if (x.delta())
                out[2 * i + 1] = bsdfEnding(p, x, f->fCos, f->pdf, q, f->jacobian,
                                            reachedFrom(scene, y.si.p, hit ? &*hit : nullptr, f->wo, true), true);
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
            terms[2 * i] = lightEnding(x, x.wi, p, baseLight(x.light), x.light.visible, x.light, edges, base.rrDepth);
        if (!x.scattered) break;
        const double eta2 = etaSquared(x, x.wi, x.wo);
        terms[2 * i + 1] = bsdfEnding(p, x, x.fCos, x.pdf, x.survival, 1, baseReached(scene, base, i), true);
        step(p, x, x.fCos, x.pdf, x.survival, eta2, 1);
    }
    return terms;
}

ShiftOutcome shiftBasePath(const Scene& scene, const BasePath& base, const std::optional<BaseVertex>& offset,
                           double shiftThreshold, std::vector<EndingTerm>& out, EarlyOut earlyOut) {
    return Shifter{scene, base, shiftThreshold, out}.run(offset, earlyOut);
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
