// Mitsuba's `phong`: the normalized modified Phong model (Lafortune and Willems 1994),
//   f_g(wi, wo) = (n + 2) / (2 pi) max(0, cos alpha)^n,  alpha the angle between wo and wi's mirror direction,
// with a Lambertian base (glossy_diffuse.h). The glossy lobe is sampled exactly around the mirror direction
// (density (n + 1) / (2 pi) cos^n alpha). Mitsuba's defaults: exponent 30, specular 0.2, diffuse 0.5. The
// exponent may be a texture: n(uv) is the mean of its channels there (Mitsuba's eval(its).average()).
#pragma once

#include <algorithm>

#include "bsdf/glossy_diffuse.h"

namespace lt {

struct PhongParams {
    std::shared_ptr<const Texture> exponent = std::make_shared<ConstantTexture>(Spectrum(30.0));
    GlossyDiffuseParams reflectances;
};

class Phong final : public GlossyDiffuseBsdf {
public:
    explicit Phong(PhongParams params);
    // Beckmann-equivalent: sqrt(2 / (n + 2)), the alpha whose lobe has the same width (as Mitsuba's
    // getRoughness).
    [[nodiscard]] double roughness(const Vec2&) const override;
    [[nodiscard]] std::string typeName() const override { return "phong"; }

private:
    [[nodiscard]] double glossy(const Vec3& wi, const Vec3& wo, const Vec2& uv) const override;
    [[nodiscard]] double glossyPdf(const Vec3& wi, const Vec3& wo, const Vec2& uv) const override;
    [[nodiscard]] std::optional<Vec3> sampleGlossy(const Vec3& wi, const Vec2& uv, const Vec2& u) const override;
    // n at uv (negative texture values read as 0).
    [[nodiscard]] double exponent(const Vec2& uv) const { return std::max(0.0, exponent_->scalar(uv)); }
    std::shared_ptr<const Texture> exponent_;
};

} // namespace lt
