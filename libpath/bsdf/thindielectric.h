// Mitsuba's `thindielectric`: a thin slab (window pane, bubble) with two smooth parallel interfaces.
// Delta reflection, and delta transmission straight through (no net bending, wo = -wi); the
// reflectance sums the slab's internal bounces, R' = R + T^2 R / (1 - R^2) with T = 1 - R (Mitsuba 0.5
// thindielectric.cpp; no absorption inside).
#pragma once

#include "bsdf/delta_bsdf.h"
#include "bsdf/dielectric_params.h"

namespace lt {

class ThinDielectric final : public DeltaBsdf {
public:
    explicit ThinDielectric(DielectricParams params);

    [[nodiscard]] std::optional<BsdfSample> sample(const Vec3& wi, const Vec2& uv, Transport mode, double uLobe,
                                                   const Vec2& u) const override;
    [[nodiscard]] std::optional<BsdfSample> deltaEval(const Vec3& wi, const Vec3& wo, const Vec2& uv,
                                                      Transport mode) const override;
    [[nodiscard]] Lobes lobes() const override { return LobeDelta | LobeReflection | LobeTransmission; }
    // Both sides see the exterior medium, so the relative index of the straight-through transmission is
    // 1: the manifold constraint is the index-matched one (the half vector vanishes at the solution, so it
    // is used unnormalized).
    [[nodiscard]] std::optional<InterfaceEta> eta() const override { return InterfaceEta{p_.extIOR, p_.extIOR}; }
    [[nodiscard]] std::string typeName() const override { return "thindielectric"; }

private:
    [[nodiscard]] double slabReflectance(const Vec3& wi) const;
    [[nodiscard]] std::optional<BsdfSample> lobeSample(const Vec3& wi, const Vec2& uv, bool reflect) const;
    DielectricParams p_;
    double eta_;
};

} // namespace lt
