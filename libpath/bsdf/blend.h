// Mitsuba's `blendbsdf`: f = (1 - w) f_0 + w f_1, the weight w in [0, 1] from a texture (its channels'
// mean, clamped; Mitsuba 0.6 blendbsdf.cpp). A sample picks BSDF 1 with probability w and is weighted with
// the mixture of both densities (one-sample MIS over the two, as Mitsuba); a delta direction both BSDFs
// share (two mirrors) is weighted with both lobes.
#pragma once

#include <memory>

#include "bsdf/bsdf.h"
#include "texture/texture.h"

namespace lt {

struct BlendParams {
    std::shared_ptr<const Texture> weight = std::make_shared<ConstantTexture>(Spectrum(0.5)); // Mitsuba default
    std::shared_ptr<const Bsdf> first, second;
};

class BlendBsdf final : public Bsdf {
public:
    // Throws lt::Error for a null BSDF or two BSDFs that refract with different indices (a vertex has one
    // interface).
    explicit BlendBsdf(BlendParams params);

    [[nodiscard]] Spectrum eval(const Vec3& wi, const Vec3& wo, const Vec2& uv, Transport mode) const override;
    [[nodiscard]] double pdf(const Vec3& wi, const Vec3& wo, const Vec2& uv) const override;
    [[nodiscard]] std::optional<BsdfSample> sample(const Vec3& wi, const Vec2& uv, Transport mode, double uLobe,
                                                   const Vec2& u) const override;
    [[nodiscard]] std::optional<BsdfSample> deltaEval(const Vec3& wi, const Vec3& wo, const Vec2& uv,
                                                      Transport mode) const override;
    [[nodiscard]] Lobes lobes() const override { return p_.first->lobes() | p_.second->lobes(); }
    // The sharper of the two parts' non-delta lobes (a purely delta part marks its own vertices as delta;
    // 0 when both parts are purely delta).
    [[nodiscard]] double roughness(const Vec2& uv) const override;
    [[nodiscard]] std::optional<InterfaceEta> eta() const override;
    [[nodiscard]] std::string typeName() const override { return "blendbsdf"; }
    [[nodiscard]] const Bsdf& first() const { return *p_.first; }
    [[nodiscard]] const Bsdf& second() const { return *p_.second; }

private:
    // w at uv: the second BSDF's share.
    [[nodiscard]] double weight(const Vec2& uv) const;
    BlendParams p_;
};

} // namespace lt
