#include "bsdf/glossy_diffuse.h"

#include <cmath>

#include "math/constants.h"
#include "util/error.h"
#include "math/warp.h"

namespace lt {

GlossyDiffuseBsdf::GlossyDiffuseBsdf(GlossyDiffuseParams params) : p_(std::move(params)) {
    if (!p_.specularReflectance || !p_.diffuseReflectance) throw Error("glossy BSDF: null reflectance texture");
    const double sum = (p_.specularReflectance->maximum() + p_.diffuseReflectance->maximum()).maxValue();
    if (p_.ensureEnergyConservation && sum > 1) scale_ = 0.99 / sum;
    const double s = p_.specularReflectance->average().luminance(), d = p_.diffuseReflectance->average().luminance();
    glossyWeight_ = s + d > 0 ? s / (s + d) : 0.5;
}

Spectrum GlossyDiffuseBsdf::eval(const Vec3& wi, const Vec3& wo, const Vec2& uv, Transport) const {
    if (wi.z <= 0 || wo.z <= 0) return {};
    return (p_.specularReflectance->eval(uv) * glossy(wi, wo, uv) + p_.diffuseReflectance->eval(uv) * InvPi) * scale_;
}

double GlossyDiffuseBsdf::pdf(const Vec3& wi, const Vec3& wo, const Vec2& uv) const {
    if (wi.z <= 0 || wo.z <= 0) return 0;
    return glossyWeight_ * glossyPdf(wi, wo, uv) + (1 - glossyWeight_) * warp::squareToCosineHemispherePdf(wo);
}

std::optional<BsdfSample> GlossyDiffuseBsdf::sample(const Vec3& wi, const Vec2& uv, Transport mode, double uLobe,
                                                    const Vec2& u) const {
    if (wi.z <= 0) return std::nullopt;
    BsdfSample s;
    if (uLobe < glossyWeight_) {
        const auto wo = sampleGlossy(wi, uv, u);
        if (!wo || wo->z <= 0) return std::nullopt;
        s.wo = *wo;
        s.lobe = LobeGlossy | LobeReflection;
    } else {
        s.wo = warp::squareToCosineHemisphere(u);
        s.lobe = LobeDiffuse | LobeReflection;
    }
    s.pdf = pdf(wi, s.wo, uv);
    if (!(s.pdf > 0) || !std::isfinite(s.pdf)) return std::nullopt;
    s.weight = eval(wi, s.wo, uv, mode) * (s.wo.z / s.pdf);
    if (!s.weight.isFinite()) return std::nullopt;
    return s;
}

} // namespace lt
