#include "bsdf/mask.h"

#include <algorithm>
#include <cmath>

#include "bsdf/delta_lobe_sum.h"
#include "util/error.h"

namespace lt {

MaskBsdf::MaskBsdf(MaskParams params) : p_(std::move(params)) {
    if (!p_.opacity || !p_.nested) throw Error("mask: needs an opacity and a nested BSDF");
    if (const auto e = p_.nested->eta(); e && e->interior != e->exterior)
        throw Error("mask: the nested BSDF '" + p_.nested->typeName() +
                    "' refracts; a cut-out's see-through part does not bend light (use a thin dielectric)");
}

std::optional<InterfaceEta> MaskBsdf::eta() const { return p_.nested->eta().value_or(InterfaceEta{1, 1}); }

Spectrum MaskBsdf::opacity(const Vec2& uv) const {
    const Spectrum a = p_.opacity->eval(uv);
    return {std::clamp(a.r, 0.0, 1.0), std::clamp(a.g, 0.0, 1.0), std::clamp(a.b, 0.0, 1.0)};
}

double MaskBsdf::nestedProbability(const Spectrum& alpha) { return std::clamp(alpha.luminance(), 0.0, 1.0); }

Spectrum MaskBsdf::eval(const Vec3& wi, const Vec3& wo, const Vec2& uv, Transport mode) const {
    return p_.nested->eval(wi, wo, uv, mode) * opacity(uv);
}

double MaskBsdf::pdf(const Vec3& wi, const Vec3& wo, const Vec2& uv) const {
    return p_.nested->pdf(wi, wo, uv) * nestedProbability(opacity(uv));
}

std::optional<BsdfSample> MaskBsdf::sample(const Vec3& wi, const Vec2& uv, Transport mode, double uLobe,
                                           const Vec2& u) const {
    const Spectrum alpha = opacity(uv);
    const double q = nestedProbability(alpha);
    if (uLobe >= q) return deltaEval(wi, -wi, uv, mode);
    auto s = p_.nested->sample(wi, uv, mode, std::min(uLobe / q, 1.0 - 1e-16), u);
    if (!s) return std::nullopt;
    if (s->lobe & LobeDelta) return deltaEval(wi, s->wo, uv, mode);
    s->weight = s->weight * alpha / q;
    s->pdf *= q;
    if (!s->weight.isFinite() || s->weight.isBlack()) return std::nullopt;
    return s;
}

std::optional<BsdfSample> MaskBsdf::deltaEval(const Vec3& wi, const Vec3& wo, const Vec2& uv, Transport mode) const {
    const Spectrum alpha = opacity(uv);
    const double q = nestedProbability(alpha);
    DeltaLobeSum sum;
    if (q > 0)
        if (const auto d = p_.nested->deltaEval(wi, wo, uv, mode)) sum.add(*d, alpha, q);
    if (q < 1 && length(wo + wi) < DeltaDirectionTolerance) {
        BsdfSample through; // straight through, index-matched: weight 1 per unit share, always taken
        through.weight = Spectrum(1.0);
        through.pdf = 1;
        through.lobe = LobeDelta | LobeTransmission;
        through.eta = 1;
        sum.add(through, Spectrum(1.0) - alpha, 1 - q);
    }
    return sum.result(wo);
}

} // namespace lt
