// Mitsuba's `roughplastic` (0.5, roughplastic.cpp): a diffuse base under a rough dielectric coating.
//   f = R_s F(wi.h) D(h) G / (4 |wi.n| |wo.n|)                               (microfacet coat, Walter 2007)
//     + R_d' T(wi) T(wo) / (pi eta^2),  R_d' = R_d / (1 - F_dr) or R_d / (1 - R_d F_dr) (`nonlinear`)
// T(mu) is the coat's transmittance at incidence cosine mu and F_dr its diffuse reflectance from inside.
// Mitsuba reads both from precomputed tables of rough-dielectric transmission. We keep it simple and
// self-contained (documented approximation):
//   * T(mu) = 1 - A(mu), A the directional albedo of the coat's own reflection lobe (R_s = 1),
//     integrated at construction on 64 cosines (uniform in sqrt(mu)) by a 32x32 midpoint rule over the
//     visible-normal sampler's unit square (the integrand is the bounded sample weight F G1; error
//     < 3e-4), linear in sqrt(mu) in between;
//   * 1 - F_dr = (2 int_0^1 T(mu) mu dmu) / eta^2, the reciprocity relation that holds exactly for a
//     smooth interface (bsdf/fresnel.h).
// With these a white base (R_d = 1, linear model) gives albedo A(mu) + T(mu) = 1 up to the table's
// interpolation error: no energy is created. Light lost to masking in the coat is counted as
// transmitted, so the diffuse part is slightly brighter than Mitsuba's at high roughness.
// Isotropic only (as in Mitsuba). The BSDF is symmetric, so the same in both transport modes.
#pragma once

#include <array>
#include <memory>

#include "bsdf/bsdf.h"
#include "bsdf/microfacet.h"
#include "bsdf/plastic.h"
#include "texture/texture.h"

namespace lt {

// The smooth plastic's parameters, and its microfacets'.
struct RoughPlasticParams : PlasticParams {
    MicrofacetType distribution = MicrofacetType::Beckmann; // Mitsuba default "beckmann"
    double alpha = 0.1;                                     // Mitsuba default
};

class RoughPlastic final : public Bsdf {
public:
    explicit RoughPlastic(RoughPlasticParams params);

    [[nodiscard]] Spectrum eval(const Vec3& wi, const Vec3& wo, const Vec2& uv, Transport mode) const override;
    [[nodiscard]] double pdf(const Vec3& wi, const Vec3& wo, const Vec2& uv) const override;
    [[nodiscard]] std::optional<BsdfSample> sample(const Vec3& wi, const Vec2& uv, Transport mode, double uLobe,
                                                   const Vec2& u) const override;
    [[nodiscard]] Lobes lobes() const override { return LobeGlossy | LobeDiffuse | LobeReflection; }
    // The coat's (the sharpest lobe's) Beckmann-equivalent alpha.
    [[nodiscard]] double roughness(const Vec2&) const override { return distr_.beckmannEquivalentAlpha(); }
    [[nodiscard]] std::string typeName() const override { return "roughplastic"; }
    // The coat transmittance T(mu) described above (exposed for tests).
    [[nodiscard]] double coatTransmittance(double mu) const;

private:
    static constexpr int TableSize = 64;
    [[nodiscard]] double specularProbability(double Ti) const;
    RoughPlasticParams p_;
    MicrofacetDistribution distr_;
    double eta_, fdrInt_, specularSamplingWeight_;
    std::array<double, TableSize> transmittance_{}; // T at sqrt(mu) = j / (TableSize - 1)
};

} // namespace lt
