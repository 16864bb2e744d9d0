#include "bsdf/plastic.h"

#include "bsdf/fresnel.h"
#include "bsdf/ior_presets.h"
#include "math/constants.h"
#include "util/error.h"
#include "math/warp.h"

namespace lt {

Plastic::Plastic(PlasticParams params) : p_(std::move(params)) {
    checkIorPair("plastic", p_.intIOR, p_.extIOR);
    if (!p_.specularReflectance || !p_.diffuseReflectance) throw Error("plastic: null texture");
    eta_ = p_.intIOR / p_.extIOR;
    fdrInt_ = fresnelDiffuseReflectance(1 / eta_);
    const double s = p_.specularReflectance->average().luminance();
    const double d = p_.diffuseReflectance->average().luminance();
    specularSamplingWeight_ = s + d > 0 ? s / (s + d) : 0.5;
}

double Plastic::specularProbability(double Fi) const {
    const double a = Fi * specularSamplingWeight_, b = (1 - Fi) * (1 - specularSamplingWeight_);
    return a + b > 0 ? a / (a + b) : 0.0;
}

Spectrum Plastic::diffuseValue(const Vec3& wi, const Vec3& wo, const Vec2& uv) const {
    const double Fi = fresnelDielectric(wi.z, eta_), Fo = fresnelDielectric(wo.z, eta_);
    Spectrum diff = p_.diffuseReflectance->eval(uv);
    if (p_.nonlinear)
        diff = diff / (Spectrum(1.0) - diff * fdrInt_);
    else
        diff /= 1 - fdrInt_;
    return diff * ((1 - Fi) * (1 - Fo) * InvPi / (eta_ * eta_));
}

Spectrum Plastic::eval(const Vec3& wi, const Vec3& wo, const Vec2& uv, Transport) const {
    if (wi.z <= 0 || wo.z <= 0) return {};
    return diffuseValue(wi, wo, uv);
}

double Plastic::pdf(const Vec3& wi, const Vec3& wo, const Vec2&) const {
    if (wi.z <= 0 || wo.z <= 0) return 0;
    return (1 - specularProbability(fresnelDielectric(wi.z, eta_))) * warp::squareToCosineHemispherePdf(wo);
}

std::optional<BsdfSample> Plastic::sample(const Vec3& wi, const Vec2& uv, Transport mode, double uLobe,
                                          const Vec2& u) const {
    if (wi.z <= 0) return std::nullopt;
    const double pSpec = specularProbability(fresnelDielectric(wi.z, eta_));
    if (uLobe < pSpec) return deltaEval(wi, Vec3(-wi.x, -wi.y, wi.z), uv, mode);
    BsdfSample s;
    s.wo = warp::squareToCosineHemisphere(u);
    s.pdf = (1 - pSpec) * warp::squareToCosineHemispherePdf(s.wo);
    if (!(s.pdf > 0)) return std::nullopt;
    s.weight = diffuseValue(wi, s.wo, uv) * (s.wo.z / s.pdf);
    s.lobe = LobeDiffuse | LobeReflection;
    return s;
}

std::optional<BsdfSample> Plastic::deltaEval(const Vec3& wi, const Vec3& wo, const Vec2& uv, Transport) const {
    if (wi.z <= 0) return std::nullopt;
    BsdfSample s;
    s.wo = Vec3(-wi.x, -wi.y, wi.z);
    if (length(s.wo - wo) >= DeltaDirectionTolerance) return std::nullopt;
    const double Fi = fresnelDielectric(wi.z, eta_);
    s.pdf = specularProbability(Fi);
    if (!(s.pdf > 0)) return std::nullopt;
    s.weight = p_.specularReflectance->eval(uv) * (Fi / s.pdf);
    s.lobe = LobeDelta | LobeReflection;
    return s;
}

} // namespace lt
