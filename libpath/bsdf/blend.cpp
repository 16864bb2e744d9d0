#include "bsdf/blend.h"

#include <algorithm>
#include <cmath>

#include "bsdf/delta_lobe_sum.h"
#include "util/error.h"

namespace lt {

BlendBsdf::BlendBsdf(BlendParams params) : p_(std::move(params)) {
    if (!p_.weight || !p_.first || !p_.second) throw Error("blendbsdf: needs a weight and two nested BSDFs");
    const auto a = p_.first->eta(), b = p_.second->eta();
    if (a && b && (a->interior != b->interior || a->exterior != b->exterior))
        throw Error("blendbsdf: the two nested BSDFs refract with different indices of refraction");
}

double BlendBsdf::weight(const Vec2& uv) const {
    const Spectrum w = p_.weight->eval(uv);
    return std::clamp((w.r + w.g + w.b) / 3, 0.0, 1.0);
}

Spectrum BlendBsdf::eval(const Vec3& wi, const Vec3& wo, const Vec2& uv, Transport mode) const {
    const double w = weight(uv);
    return p_.first->eval(wi, wo, uv, mode) * (1 - w) + p_.second->eval(wi, wo, uv, mode) * w;
}

double BlendBsdf::pdf(const Vec3& wi, const Vec3& wo, const Vec2& uv) const {
    const double w = weight(uv);
    return p_.first->pdf(wi, wo, uv) * (1 - w) + p_.second->pdf(wi, wo, uv) * w;
}

std::optional<BsdfSample> BlendBsdf::sample(const Vec3& wi, const Vec2& uv, Transport mode, double uLobe,
                                            const Vec2& u) const {
    const double w = weight(uv);
    const bool second = uLobe >= 1 - w;
    // The lobe variable, rescaled to [0, 1) within the chosen BSDF's share.
    const double uNested = second ? (uLobe - (1 - w)) / w : uLobe / (1 - w);
    auto s = (second ? p_.second : p_.first)->sample(wi, uv, mode, std::min(uNested, 1.0 - 1e-16), u);
    if (!s) return std::nullopt;
    if (s->lobe & LobeDelta) return deltaEval(wi, s->wo, uv, mode);
    s->pdf = pdf(wi, s->wo, uv);
    if (!(s->pdf > 0) || !std::isfinite(s->pdf)) return std::nullopt;
    s->weight = eval(wi, s->wo, uv, mode) * (std::abs(s->wo.z) / s->pdf);
    if (!s->weight.isFinite() || s->weight.isBlack()) return std::nullopt;
    return s;
}

std::optional<BsdfSample> BlendBsdf::deltaEval(const Vec3& wi, const Vec3& wo, const Vec2& uv, Transport mode) const {
    const double w = weight(uv);
    DeltaLobeSum sum;
    if (w < 1)
        if (const auto a = p_.first->deltaEval(wi, wo, uv, mode)) sum.add(*a, Spectrum(1 - w), 1 - w);
    if (w > 0)
        if (const auto b = p_.second->deltaEval(wi, wo, uv, mode)) sum.add(*b, Spectrum(w), w);
    return sum.result(wo);
}

double BlendBsdf::roughness(const Vec2& uv) const {
    const auto scatters = [](const Bsdf& b) { return b.hasGlossy() || b.hasDiffuse(); };
    if (scatters(*p_.first) && scatters(*p_.second)) return std::min(p_.first->roughness(uv), p_.second->roughness(uv));
    if (scatters(*p_.first)) return p_.first->roughness(uv);
    if (scatters(*p_.second)) return p_.second->roughness(uv);
    return 0;
}

std::optional<InterfaceEta> BlendBsdf::eta() const { return p_.first->eta() ? p_.first->eta() : p_.second->eta(); }

} // namespace lt
