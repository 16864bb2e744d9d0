// Mitsuba's `roughconductor`: a rough metal, the Cook-Torrance microfacet BRDF
// f = F(i.h) D(h) G(i, o, h) / (4 |i.n| |o.n|) (Walter et al. 2007 Eq. 20) with the exact conductor
// Fresnel term, sampled through the visible normals of the distribution (bsdf/microfacet.h).
#pragma once

#include <memory>

#include "bsdf/bsdf.h"
#include "bsdf/conductor.h"
#include "bsdf/conductor_presets.h"
#include "bsdf/microfacet.h"
#include "texture/texture.h"

namespace lt {

// The smooth conductor's parameters, and its microfacets'.
struct RoughConductorParams : ConductorParams {
    MicrofacetType distribution = MicrofacetType::Beckmann; // Mitsuba default "beckmann"
    double alphaU = 0.1, alphaV = 0.1;                      // Mitsuba default alpha 0.1; `alpha` sets both
};

class RoughConductor final : public Bsdf {
public:
    explicit RoughConductor(RoughConductorParams params);

    [[nodiscard]] Spectrum eval(const Vec3& wi, const Vec3& wo, const Vec2& uv, Transport mode) const override;
    [[nodiscard]] double pdf(const Vec3& wi, const Vec3& wo, const Vec2& uv) const override;
    [[nodiscard]] std::optional<BsdfSample> sample(const Vec3& wi, const Vec2& uv, Transport mode, double uLobe,
                                                   const Vec2& u) const override;
    [[nodiscard]] Lobes lobes() const override { return LobeGlossy | LobeReflection; }
    [[nodiscard]] double roughness(const Vec2&) const override { return distr_.beckmannEquivalentAlpha(); }
    [[nodiscard]] std::string typeName() const override { return "roughconductor"; }
    [[nodiscard]] const MicrofacetDistribution& distribution() const { return distr_; }

private:
    RoughConductorParams p_;
    MicrofacetDistribution distr_;
};

} // namespace lt
