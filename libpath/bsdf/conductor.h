// Mitsuba's `conductor`: a smooth metal, delta reflection weighted by the exact conductor Fresnel
// reflectance (bsdf/fresnel.h) and a specular reflectance multiplier.
#pragma once

#include <memory>

#include "bsdf/delta_bsdf.h"
#include "bsdf/conductor_presets.h"
#include "texture/texture.h"

namespace lt {

// Named materials ("Cu", "Au", "none", ...) are resolved with lookupConductor (bsdf/conductor_presets.h).
struct ConductorParams {
    Spectrum eta = lookupConductor("Cu")->eta; // Mitsuba default material "Cu"
    Spectrum k = lookupConductor("Cu")->k;
    double extEta = 1.000277;                  // Mitsuba default "air"; eta and k are divided by it
    std::shared_ptr<const Texture> specularReflectance = std::make_shared<ConstantTexture>(Spectrum(1.0));
};

class Conductor final : public DeltaBsdf {
public:
    explicit Conductor(ConductorParams params);

    [[nodiscard]] std::optional<BsdfSample> sample(const Vec3& wi, const Vec2& uv, Transport mode, double uLobe,
                                                   const Vec2& u) const override;
    [[nodiscard]] std::optional<BsdfSample> deltaEval(const Vec3& wi, const Vec3& wo, const Vec2& uv,
                                                      Transport mode) const override;
    [[nodiscard]] Lobes lobes() const override { return LobeDelta | LobeReflection; }
    [[nodiscard]] std::string typeName() const override { return "conductor"; }

private:
    ConductorParams p_;
};

// Checks eta, k >= 0, finite, and extEta > 0; throws lt::Error naming the plugin. Shared with
// roughconductor.
void checkConductorParams(const std::string& plugin, const Spectrum& eta, const Spectrum& k, double extEta);

} // namespace lt
