// Mitsuba's `roughdielectric`: a rough interface between two dielectrics, Walter et al. 2007
// ("Microfacet Models for Refraction through Rough Surfaces"): microfacet reflection (Eq. 20) and
// refraction (Eq. 21) with the exact dielectric Fresnel term at the microfacet, chosen by Fresnel after
// sampling a visible normal. Both sides are handled (Walter Sec. 5.2: the sampler mirrors wi below).
//
// Refraction in the two transport modes (bsdf.h): with eta = eta_wo / eta_wi,
//   f_Importance(wi, wo) = |wi.h| |wo.h| / (|wi.n| |wo.n|) eta^2 (1 - F) D G / (wi.h + eta wo.h)^2,
//   f_Radiance(wi, wo)   = f_Importance(wi, wo) / eta^2 = f_Importance(wo, wi)
// (Walter Eq. 21; the adjoint of Veach thesis 5.2, the factor Mitsuba 0.5 adds for bidirectional use).
#pragma once

#include "bsdf/bsdf.h"
#include "bsdf/dielectric_params.h"
#include "bsdf/microfacet.h"

namespace lt {

// The interface's parameters, and its microfacets'.
struct RoughDielectricParams : DielectricParams {
    MicrofacetType distribution = MicrofacetType::Beckmann; // Mitsuba default "beckmann"
    double alphaU = 0.1, alphaV = 0.1;                      // Mitsuba default alpha 0.1; `alpha` sets both
};

class RoughDielectric final : public Bsdf {
public:
    explicit RoughDielectric(RoughDielectricParams params);

    [[nodiscard]] Spectrum eval(const Vec3& wi, const Vec3& wo, const Vec2& uv, Transport mode) const override;
    [[nodiscard]] double pdf(const Vec3& wi, const Vec3& wo, const Vec2& uv) const override;
    [[nodiscard]] std::optional<BsdfSample> sample(const Vec3& wi, const Vec2& uv, Transport mode, double uLobe,
                                                   const Vec2& u) const override;
    [[nodiscard]] Lobes lobes() const override { return LobeGlossy | LobeReflection | LobeTransmission; }
    [[nodiscard]] double roughness(const Vec2&) const override { return distr_.beckmannEquivalentAlpha(); }
    [[nodiscard]] std::optional<InterfaceEta> eta() const override { return InterfaceEta{p_.intIOR, p_.extIOR}; }
    [[nodiscard]] std::string typeName() const override { return "roughdielectric"; }
    [[nodiscard]] const MicrofacetDistribution& distribution() const { return distr_; }

private:
    // eta_wo / eta_wi for a refraction leaving wi's side.
    [[nodiscard]] double etaRel(const Vec3& wi) const { return wi.z > 0 ? eta_ : 1 / eta_; }
    RoughDielectricParams p_;
    MicrofacetDistribution distr_;
    double eta_; // intIOR / extIOR
};

} // namespace lt
