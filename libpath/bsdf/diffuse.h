// Mitsuba's `diffuse`: an ideal one-sided Lambertian reflector, f = R / pi on the front side only
// (wrap it in `twosided` to reflect on both sides, as Mitsuba scenes do).
#pragma once

#include <memory>

#include "bsdf/bsdf.h"
#include "texture/texture.h"

namespace lt {

struct DiffuseParams {
    std::shared_ptr<const Texture> reflectance = std::make_shared<ConstantTexture>(Spectrum(0.5)); // Mitsuba default
};

class Diffuse final : public Bsdf {
public:
    explicit Diffuse(DiffuseParams params);

    [[nodiscard]] Spectrum eval(const Vec3& wi, const Vec3& wo, const Vec2& uv, Transport mode) const override;
    [[nodiscard]] double pdf(const Vec3& wi, const Vec3& wo, const Vec2& uv) const override;
    [[nodiscard]] std::optional<BsdfSample> sample(const Vec3& wi, const Vec2& uv, Transport mode, double uLobe,
                                                   const Vec2& u) const override;
    [[nodiscard]] Lobes lobes() const override { return LobeDiffuse | LobeReflection; }
    [[nodiscard]] double roughness(const Vec2&) const override;
    [[nodiscard]] std::string typeName() const override { return "diffuse"; }

private:
    DiffuseParams p_;
};

} // namespace lt
