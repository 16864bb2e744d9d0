// Mitsuba's `thindielectric`: a thin slab (window pane, bubble) with two smooth parallel interfaces.
// Delta reflection, and delta transmission straight through (no net bending, wo = -wi); the
// reflectance sums the slab's internal bounces, R' = R + T^2 R / (1 - R^2) with T = 1 - R (Mitsuba 0.5
// thindielectric.cpp; no absorption inside).
#pragma once

#include <memory>

#include "bsdf/bsdf.h"
#include "texture/texture.h"

namespace lt {

struct ThinDielectricParams {
    double intIOR = 1.5046;   // Mitsuba default "bk7"
    double extIOR = 1.000277; // Mitsuba default "air"
    std::shared_ptr<const Texture> specularReflectance = std::make_shared<ConstantTexture>(Spectrum(1.0));
    std::shared_ptr<const Texture> specularTransmittance = std::make_shared<ConstantTexture>(Spectrum(1.0));
};

class ThinDielectric final : public Bsdf {
public:
    explicit ThinDielectric(ThinDielectricParams params);

    [[nodiscard]] Spectrum eval(const Vec3&, const Vec3&, const Vec2&, Transport) const override { return {}; }
    [[nodiscard]] double pdf(const Vec3&, const Vec3&, const Vec2&) const override { return 0; }
    [[nodiscard]] std::optional<BsdfSample> sample(const Vec3& wi, const Vec2& uv, Transport mode, double uLobe,
                                                   const Vec2& u) const override;
    [[nodiscard]] std::optional<BsdfSample> deltaEval(const Vec3& wi, const Vec3& wo, const Vec2& uv,
                                                      Transport mode) const override;
    [[nodiscard]] Lobes lobes() const override { return LobeDelta | LobeReflection | LobeTransmission; }
    [[nodiscard]] double roughness(const Vec2&) const override { return 0; }
    // Both sides see the exterior medium, so the relative index of the straight-through transmission is
    // 1: the manifold constraint is the index-matched one (the half vector vanishes at the solution, so it
    // is used unnormalized).
    [[nodiscard]] std::optional<InterfaceEta> eta() const override { return InterfaceEta{p_.extIOR, p_.extIOR}; }
    [[nodiscard]] std::string typeName() const override { return "thindielectric"; }

private:
    [[nodiscard]] double slabReflectance(const Vec3& wi) const;
    [[nodiscard]] std::optional<BsdfSample> lobeSample(const Vec3& wi, const Vec2& uv, bool reflect) const;
    ThinDielectricParams p_;
    double eta_;
};

} // namespace lt
