#include "bsdf/shading_correction.h"

#include <cmath>

namespace lt {

double WorldBsdf::shadingFactor(const Vec3& wiWorld, const Vec3& woWorld, Transport mode) const {
    const double ig = dot(wiWorld, ng), og = dot(woWorld, ng);
    const double is = dot(wiWorld, shading.n), os = dot(woWorld, shading.n);
    if (ig == 0 || og == 0 || is == 0 || os == 0) return 0;
    // Reflection vs transmission must agree between the geometric and the shading normal.
    if ((ig * og > 0) != (is * os > 0)) return 0;
    return mode == Transport::Radiance ? std::abs(os / og) : std::abs(is / ig);
}

Spectrum WorldBsdf::eval(const Vec3& wiWorld, const Vec3& woWorld, Transport mode) const {
    const double factor = shadingFactor(wiWorld, woWorld, mode);
    if (factor == 0) return {};
    return bsdf.eval(shading.toLocal(wiWorld), shading.toLocal(woWorld), uv, mode) * factor;
}

double WorldBsdf::pdf(const Vec3& wiWorld, const Vec3& woWorld) const {
    return bsdf.pdf(shading.toLocal(wiWorld), shading.toLocal(woWorld), uv);
}

namespace {

// Turns a local sample into a world one: side test against the sampled lobe, and the weight factor
// |wi.ns| |wo.ng| / (|wi.ng| |wo.ns|) in Importance mode (Veach Eq. 5.21; see the header).
std::optional<BsdfSample> toWorld(const WorldBsdf& w, const Vec3& wiWorld, std::optional<BsdfSample> s,
                                  Transport mode) {
    if (!s) return std::nullopt;
    s->wo = w.shading.toWorld(s->wo);
    const double ig = dot(wiWorld, w.ng), og = dot(s->wo, w.ng);
    const bool geometricReflection = ig * og > 0;
    if (ig == 0 || og == 0 || geometricReflection != bool(s->lobe & LobeReflection)) return std::nullopt;
    if (mode == Transport::Importance) {
        const double is = dot(wiWorld, w.shading.n), os = dot(s->wo, w.shading.n);
        if (os == 0) return std::nullopt;
        s->weight *= std::abs(is * og / (ig * os));
    }
    if (!s->weight.isFinite()) return std::nullopt;
    return s;
}

} // namespace

std::optional<BsdfSample> WorldBsdf::sample(const Vec3& wiWorld, Transport mode, double uLobe, const Vec2& u) const {
    return toWorld(*this, wiWorld, bsdf.sample(shading.toLocal(wiWorld), uv, mode, uLobe, u), mode);
}

std::optional<BsdfSample> WorldBsdf::deltaEval(const Vec3& wiWorld, const Vec3& woWorld, Transport mode) const {
    return toWorld(*this, wiWorld, bsdf.deltaEval(shading.toLocal(wiWorld), shading.toLocal(woWorld), uv, mode), mode);
}

} // namespace lt
