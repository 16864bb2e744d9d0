// Mitsuba's `dielectric`: a smooth interface between two dielectrics. Delta reflection and delta
// refraction, one of them chosen with the exact Fresnel reflectance as probability (so the Fresnel
// factor cancels from the weights). The interior lies below the shading normal.
#pragma once

#include "bsdf/delta_bsdf.h"
#include "bsdf/dielectric_params.h"

namespace lt {

class Dielectric final : public DeltaBsdf {
public:
    // Throws lt::Error for a non-positive or non-finite index or a null texture.
    explicit Dielectric(DielectricParams params);

    [[nodiscard]] std::optional<BsdfSample> sample(const Vec3& wi, const Vec2& uv, Transport mode, double uLobe,
                                                   const Vec2& u) const override;
    [[nodiscard]] std::optional<BsdfSample> deltaEval(const Vec3& wi, const Vec3& wo, const Vec2& uv,
                                                      Transport mode) const override;
    [[nodiscard]] Lobes lobes() const override { return LobeDelta | LobeReflection | LobeTransmission; }
    [[nodiscard]] std::optional<InterfaceEta> eta() const override { return InterfaceEta{p_.intIOR, p_.extIOR}; }
    [[nodiscard]] std::string typeName() const override { return "dielectric"; }

private:
    // The reflected or refracted sample for wi with its Fresnel probability; nothing under total
    // internal reflection when refraction is asked for.
    [[nodiscard]] std::optional<BsdfSample> lobeSample(const Vec3& wi, const Vec2& uv, Transport mode,
                                                       bool reflect) const;
    DielectricParams p_;
    double eta_; // intIOR / extIOR
};

} // namespace lt
