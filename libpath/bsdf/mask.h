// Mitsuba's `mask`: a cut-out (leaves, fences) as an opacity alpha(uv) in [0, 1] over a nested BSDF,
//   f = alpha f_nested,  plus a delta lobe straight through (wo = -wi, eta 1) carrying 1 - alpha
// (Mitsuba 0.6 mask.cpp; alpha per channel, the lobe chosen by its luminance). The straight-through lobe
// is a vertex of the path like a thin dielectric's transmission: an index-matched interface (eta() equal
// indices), which every method follows as a refraction that does not bend; shadow rays stop at it, and it
// counts toward the path depth.
#pragma once

#include <memory>

#include "bsdf/bsdf.h"
#include "texture/texture.h"

namespace lt {

struct MaskParams {
    std::shared_ptr<const Texture> opacity = std::make_shared<ConstantTexture>(Spectrum(0.5)); // Mitsuba default
    std::shared_ptr<const Bsdf> nested;
};

class MaskBsdf final : public Bsdf {
public:
    // Throws lt::Error for a null texture or BSDF, or a nested BSDF that refracts (a vertex has one
    // interface, and the see-through part does not bend light).
    explicit MaskBsdf(MaskParams params);

    [[nodiscard]] Spectrum eval(const Vec3& wi, const Vec3& wo, const Vec2& uv, Transport mode) const override;
    [[nodiscard]] double pdf(const Vec3& wi, const Vec3& wo, const Vec2& uv) const override;
    [[nodiscard]] std::optional<BsdfSample> sample(const Vec3& wi, const Vec2& uv, Transport mode, double uLobe,
                                                   const Vec2& u) const override;
    [[nodiscard]] std::optional<BsdfSample> deltaEval(const Vec3& wi, const Vec3& wo, const Vec2& uv,
                                                      Transport mode) const override;
    [[nodiscard]] Lobes lobes() const override { return p_.nested->lobes() | LobeDelta | LobeTransmission; }
    // The nested BSDF's (as Mitsuba): the straight-through lobe is delta and marks its vertices so itself;
    // the roughness classifies the vertices the nested lobes scatter at.
    [[nodiscard]] double roughness(const Vec2& uv) const override { return p_.nested->roughness(uv); }
    // Equal indices: the nested BSDF's when it has them (a thin dielectric), 1 otherwise.
    [[nodiscard]] std::optional<InterfaceEta> eta() const override;
    [[nodiscard]] std::string typeName() const override { return "mask"; }
    [[nodiscard]] const Bsdf& nested() const { return *p_.nested; }

private:
    // alpha at uv, each channel clamped to [0, 1], and the probability of the nested BSDF (its luminance).
    [[nodiscard]] Spectrum opacity(const Vec2& uv) const;
    [[nodiscard]] static double nestedProbability(const Spectrum& alpha);
    MaskParams p_;
};

} // namespace lt
