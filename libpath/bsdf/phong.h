// Mitsuba's `phong`: the normalized modified Phong model (Lafortune and Willems 1994),
//   f_g(wi, wo) = (n + 2) / (2 pi) max(0, cos alpha)^n,  alpha the angle between wo and wi's mirror direction,
// with a Lambertian base (glossy_diffuse.h). The glossy lobe is sampled exactly around the mirror direction
// (density (n + 1) / (2 pi) cos^n alpha). Mitsuba's defaults: exponent 30, specular 0.2, diffuse 0.5.
#pragma once

#include "bsdf/glossy_diffuse.h"

namespace lt {

struct PhongParams {
    double exponent = 30;
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
    [[nodiscard]] double glossy(const Vec3& wi, const Vec3& wo) const override;
    [[nodiscard]] double glossyPdf(const Vec3& wi, const Vec3& wo) const override;
    [[nodiscard]] std::optional<Vec3> sampleGlossy(const Vec3& wi, const Vec2& u) const override;
    double n_;
};

} // namespace lt
