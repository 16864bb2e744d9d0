// The structure Mitsuba's `phong` and `ward` share: a glossy reflection lobe scaled by the specular
// reflectance plus a Lambertian lobe scaled by the diffuse reflectance, front side only,
//   f(wi, wo) = R_s f_g(wi, wo) + R_d / pi,
// sampled by picking the glossy lobe with probability w = lum(mean R_s) / (lum(mean R_s) + lum(mean R_d))
// and weighted with the one-sample mixture density w p_g + (1 - w) cos / pi (Mitsuba 0.6, phong.cpp and
// ward.cpp). Where the reflectances' maxima sum above 1 in some channel, Mitsuba scales both by 0.99 over
// that sum (ensureEnergyConservation, on by default); so does lt, and the loader says so. Both lobes are
// symmetric in wi and wo, so f is the same in both transport modes.
#pragma once

#include <memory>

#include "bsdf/bsdf.h"
#include "texture/texture.h"

namespace lt {

struct GlossyDiffuseParams {
    std::shared_ptr<const Texture> specularReflectance = std::make_shared<ConstantTexture>(Spectrum(0.2)); // Mitsuba
    std::shared_ptr<const Texture> diffuseReflectance = std::make_shared<ConstantTexture>(Spectrum(0.5));  // defaults
    bool ensureEnergyConservation = true;
};

class GlossyDiffuseBsdf : public Bsdf {
public:
    [[nodiscard]] Spectrum eval(const Vec3& wi, const Vec3& wo, const Vec2& uv, Transport mode) const final;
    [[nodiscard]] double pdf(const Vec3& wi, const Vec3& wo, const Vec2& uv) const final;
    [[nodiscard]] std::optional<BsdfSample> sample(const Vec3& wi, const Vec2& uv, Transport mode, double uLobe,
                                                   const Vec2& u) const final;
    [[nodiscard]] Lobes lobes() const final { return LobeGlossy | LobeDiffuse | LobeReflection; }
    // The factor both reflectances were scaled by: 1 when they conserve energy as given.
    [[nodiscard]] double energyScale() const { return scale_; }

protected:
    explicit GlossyDiffuseBsdf(GlossyDiffuseParams params);
    // The glossy lobe per unit specular reflectance, f_g(wi, wo), for wi and wo above the surface; uv selects
    // the lobe's texture values (phong's exponent, ward's alphas).
    [[nodiscard]] virtual double glossy(const Vec3& wi, const Vec3& wo, const Vec2& uv) const = 0;
    // The solid-angle density with which sampleGlossy produces wo.
    [[nodiscard]] virtual double glossyPdf(const Vec3& wi, const Vec3& wo, const Vec2& uv) const = 0;
    // A direction from the glossy lobe's sampler (possibly below the surface: then the sample is lost).
    [[nodiscard]] virtual std::optional<Vec3> sampleGlossy(const Vec3& wi, const Vec2& uv, const Vec2& u) const = 0;

private:
    GlossyDiffuseParams p_;
    double scale_ = 1;
    double glossyWeight_ = 0.5; // w above
};

} // namespace lt
