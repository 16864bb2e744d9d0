#include "bsdf/roughconductor.h"

#include "bsdf/conductor.h"
#include "bsdf/fresnel.h"
#include "bsdf/half_vector.h"
#include "util/error.h"

namespace lt {

RoughConductor::RoughConductor(RoughConductorParams params)
    : p_(std::move(params)), distr_(p_.distribution, p_.alphaU, p_.alphaV) {
    checkConductorParams("roughconductor", p_.eta, p_.k, p_.extEta);
    if (!(p_.alphaU > 0) || !(p_.alphaV > 0) || !std::isfinite(p_.alphaU) || !std::isfinite(p_.alphaV))
        throw Error("roughconductor: alpha must be positive and finite");
    if (!p_.specularReflectance) throw Error("roughconductor: null texture");
    p_.eta /= p_.extEta;
    p_.k /= p_.extEta;
}

Spectrum RoughConductor::eval(const Vec3& wi, const Vec3& wo, const Vec2& uv, Transport) const {
    if (wi.z <= 0 || wo.z <= 0) return {};
    const auto h = halfVector(wi, wo, 1);
    if (!h) return {};
    const double DG = distr_.D(*h) * distr_.G(wi, wo, *h);
    if (!(DG > 0)) return {};
    return p_.specularReflectance->eval(uv) * fresnelConductor(dot(wi, *h), p_.eta, p_.k) * (DG / (4 * wi.z * wo.z));
}

double RoughConductor::pdf(const Vec3& wi, const Vec3& wo, const Vec2&) const {
    if (wi.z <= 0 || wo.z <= 0) return 0;
    const auto h = halfVector(wi, wo, 1);
    if (!h) return 0;
    return distr_.pdfVisible(wi, *h) * halfVectorJacobian(*h, wi, wo, 1);
}

std::optional<BsdfSample> RoughConductor::sample(const Vec3& wi, const Vec2& uv, Transport, double,
                                                 const Vec2& u) const {
    if (wi.z <= 0) return std::nullopt;
    const Vec3 m = distr_.sampleVisible(wi, u);
    BsdfSample s;
    s.wo = reflect(wi, m);
    if (s.wo.z <= 0) return std::nullopt;
    s.pdf = distr_.pdfVisible(wi, m) * halfVectorJacobian(m, wi, s.wo, 1);
    if (!(s.pdf > 0) || !std::isfinite(s.pdf)) return std::nullopt;
    // f cos / pdf = F D G / (4 |i.n|) / (G1(i) D / (4 |i.n|)) = F G1(o): Heitz 2014 Sec. 5.
    s.weight = p_.specularReflectance->eval(uv) * fresnelConductor(dot(wi, m), p_.eta, p_.k) * distr_.G1(s.wo, m);
    s.lobe = LobeGlossy | LobeReflection;
    return s;
}

} // namespace lt
