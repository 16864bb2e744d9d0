// Mitsuba's `plastic` (0.5, plastic.cpp): a diffuse base under a smooth dielectric coating. Delta
// specular reflection off the coating with Fresnel reflectance F(wi); a diffuse lobe for the light that
// enters, scatters in the base and leaves, with the internal reflections at the coating summed:
//   f_diffuse = R_d / (1 - F_dr,int)          (linear model, Mitsuba's default)
//            or R_d / (1 - R_d F_dr,int)        (`nonlinear`: a multiply-scattered base darkens and saturates)
//             * (1 - F(wi)) (1 - F(wo)) / (pi eta^2),
// where F_dr,int is the diffuse Fresnel reflectance of the coating seen from inside. The diffuse part is
// symmetric in wi and wo, so the BSDF is the same in both transport modes.
#pragma once

#include <memory>

#include "bsdf/bsdf.h"
#include "texture/texture.h"

namespace lt {

struct PlasticParams {
    double intIOR = 1.49;     // Mitsuba default "polypropylene"
    double extIOR = 1.000277; // Mitsuba default "air"
    std::shared_ptr<const Texture> specularReflectance = std::make_shared<ConstantTexture>(Spectrum(1.0));
    std::shared_ptr<const Texture> diffuseReflectance = std::make_shared<ConstantTexture>(Spectrum(0.5));
    bool nonlinear = false;
};

class Plastic final : public Bsdf {
public:
    explicit Plastic(PlasticParams params);

    [[nodiscard]] Spectrum eval(const Vec3& wi, const Vec3& wo, const Vec2& uv, Transport mode) const override;
    [[nodiscard]] double pdf(const Vec3& wi, const Vec3& wo, const Vec2& uv) const override;
    [[nodiscard]] std::optional<BsdfSample> sample(const Vec3& wi, const Vec2& uv, Transport mode, double uLobe,
                                                   const Vec2& u) const override;
    [[nodiscard]] std::optional<BsdfSample> deltaEval(const Vec3& wi, const Vec3& wo, const Vec2& uv,
                                                      Transport mode) const override;
    [[nodiscard]] Lobes lobes() const override { return LobeDelta | LobeDiffuse | LobeReflection; }
    // 0: the sharpest lobe is a mirror.
    [[nodiscard]] double roughness(const Vec2&) const override { return 0; }
    [[nodiscard]] std::string typeName() const override { return "plastic"; }

private:
    // Probability of choosing the specular lobe: Fresnel weighted by the average reflectances
    // (Mitsuba 0.5: specularSamplingWeight = s / (s + d) with luminances of the texture averages).
    [[nodiscard]] double specularProbability(double Fi) const;
    [[nodiscard]] Spectrum diffuseValue(const Vec3& wi, const Vec3& wo, const Vec2& uv) const;
    PlasticParams p_;
    double eta_, fdrInt_, specularSamplingWeight_;
};

} // namespace lt
