// Mitsuba's `dielectric`: a smooth interface between two dielectrics. Delta reflection and delta
// refraction, one of them chosen with the exact Fresnel reflectance as probability (so the Fresnel
// factor cancels from the weights). The interior lies below the shading normal.
#pragma once

#include <memory>

#include "bsdf/bsdf.h"
#include "texture/texture.h"

namespace lt {

// Indices are numbers here; names ("bk7", "air", ...) are resolved with lookupIor (bsdf/ior_presets.h).
struct DielectricParams {
    double intIOR = 1.5046;   // Mitsuba default "bk7"
    double extIOR = 1.000277; // Mitsuba default "air"
    std::shared_ptr<const Texture> specularReflectance = std::make_shared<ConstantTexture>(Spectrum(1.0));
    std::shared_ptr<const Texture> specularTransmittance = std::make_shared<ConstantTexture>(Spectrum(1.0));
};

class Dielectric final : public Bsdf {
public:
    // Throws lt::Error for a non-positive or non-finite index or a null texture.
    explicit Dielectric(DielectricParams params);

    [[nodiscard]] Spectrum eval(const Vec3&, const Vec3&, const Vec2&, Transport) const override { return {}; }
    [[nodiscard]] double pdf(const Vec3&, const Vec3&, const Vec2&) const override { return 0; }
    [[nodiscard]] std::optional<BsdfSample> sample(const Vec3& wi, const Vec2& uv, Transport mode, double uLobe,
                                                   const Vec2& u) const override;
    [[nodiscard]] std::optional<BsdfSample> deltaEval(const Vec3& wi, const Vec3& wo, const Vec2& uv,
                                                      Transport mode) const override;
    [[nodiscard]] Lobes lobes() const override { return LobeDelta | LobeReflection | LobeTransmission; }
    [[nodiscard]] double roughness(const Vec2&) const override { return 0; }
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
