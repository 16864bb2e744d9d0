#include "bsdf/roughdielectric.h"

#include <cmath>

#include "bsdf/fresnel.h"
#include "bsdf/half_vector.h"
#include "bsdf/ior_presets.h"
#include "util/error.h"
#include "math/numeric.h"

namespace lt {

RoughDielectric::RoughDielectric(RoughDielectricParams params)
    : p_(std::move(params)), distr_(p_.distribution, p_.alphaU, p_.alphaV), eta_(p_.relativeEta("roughdielectric")) {
    if (!(p_.alphaU > 0) || !(p_.alphaV > 0) || !std::isfinite(p_.alphaU) || !std::isfinite(p_.alphaV))
        throw Error("roughdielectric: alpha must be positive and finite");
}

Spectrum RoughDielectric::eval(const Vec3& wi, const Vec3& wo, const Vec2& uv, Transport mode) const {
    if (wi.z == 0 || wo.z == 0) return {};
    const bool reflect = wi.z * wo.z > 0;
    const double eta = reflect ? 1.0 : etaRel(wi);
    const auto h = halfVector(wi, wo, eta);
    if (!h) return {};
    const double D = distr_.D(*h);
    const double G = distr_.G(wi, wo, *h); // includes the side tests chi+(v.h / v.n)
    if (!(D * G > 0)) return {};
    const double F = fresnelDielectric(dot(wi, *h), eta_);
    if (reflect) return p_.specularReflectance->eval(uv) * (F * D * G / (4 * std::abs(wi.z * wo.z)));
    const double denom = sqr(dot(wi, *h) + eta * dot(wo, *h));
    if (!(denom > 0)) return {};
    double value = std::abs(dot(wi, *h) * dot(wo, *h) / (wi.z * wo.z)) * eta * eta * (1 - F) * D * G / denom;
    if (mode == Transport::Radiance) value /= eta * eta;
    return std::isfinite(value) ? p_.specularTransmittance->eval(uv) * value : Spectrum();
}

double RoughDielectric::pdf(const Vec3& wi, const Vec3& wo, const Vec2&) const {
    if (wi.z == 0 || wo.z == 0) return 0;
    const bool reflect = wi.z * wo.z > 0;
    const double eta = reflect ? 1.0 : etaRel(wi);
    const auto h = halfVector(wi, wo, eta);
    if (!h) return 0;
    // Only microfacets facing both directions are ever produced by sample().
    if (dot(wi, *h) * wi.z <= 0 || dot(wo, *h) * wo.z <= 0) return 0;
    const double F = fresnelDielectric(dot(wi, *h), eta_);
    const double pdf = distr_.pdfVisible(wi, *h) * (reflect ? F : 1 - F) * halfVectorJacobian(*h, wi, wo, eta);
    return std::isfinite(pdf) ? pdf : 0.0;
}

std::optional<BsdfSample> RoughDielectric::sample(const Vec3& wi, const Vec2& uv, Transport mode, double uLobe,
                                                  const Vec2& u) const {
    if (wi.z == 0) return std::nullopt;
    const Vec3 m = distr_.sampleVisible(wi, u);
    const double pdfM = distr_.pdfVisible(wi, m);
    if (!(pdfM > 0)) return std::nullopt;
    const double F = fresnelDielectric(dot(wi, m), eta_);
    BsdfSample s;
    if (uLobe < F) {
        s.wo = reflect(wi, m);
        if (s.wo.z * wi.z <= 0) return std::nullopt;
        s.pdf = pdfM * F * halfVectorJacobian(m, wi, s.wo, 1);
        s.weight = p_.specularReflectance->eval(uv); // times G1(o, m) below: F D G / (4|i.n|) / (F G1(i) D / (4|i.n|))
        s.lobe = LobeGlossy | LobeReflection;
        s.eta = 1;
    } else {
        const double eta = etaRel(wi);
        const auto wo = refract(wi, m, eta);
        if (!wo || wo->z * wi.z >= 0) return std::nullopt;
        s.wo = *wo;
        s.pdf = pdfM * (1 - F) * halfVectorJacobian(m, wi, s.wo, eta);
        // The (1 - F), D, |i.h| / |i.n| and Walter's Jacobian cancel against the pdf: G1(o, m) remains.
        s.weight = p_.specularTransmittance->eval(uv);
        if (mode == Transport::Radiance) s.weight *= 1 / (eta * eta);
        s.lobe = LobeGlossy | LobeTransmission;
        s.eta = eta;
    }
    const double G1o = distr_.G1(s.wo, m);
    if (!(s.pdf > 0) || !std::isfinite(s.pdf) || !(G1o > 0)) return std::nullopt;
    s.weight *= G1o;
    return s;
}

} // namespace lt
