// Mitsuba's `bumpmap`: a nested BSDF seen through a shading frame tilted by a displacement texture
// (Mitsuba 0.6 bumpmap.cpp; Blinn 1978). The BSDF itself is the nested one, unchanged, in the tilted frame:
// the tilt is a property of the surface point, so scene/bump_frame.h applies it where the surface's
// differential geometry is made (Shape::surfaceAt), and every method sees the same frame. This class only
// carries the displacement to the shapes and forwards to the nested BSDF.
#pragma once

#include <memory>

#include "bsdf/bsdf.h"
#include "texture/texture.h"

namespace lt {

class BumpMappedBsdf final : public Bsdf {
public:
    // Throws lt::Error for a null texture or BSDF.
    BumpMappedBsdf(std::shared_ptr<const Texture> displacement, std::shared_ptr<const Bsdf> nested);

    [[nodiscard]] Spectrum eval(const Vec3& wi, const Vec3& wo, const Vec2& uv, Transport mode) const override {
        return nested_->eval(wi, wo, uv, mode);
    }
    [[nodiscard]] double pdf(const Vec3& wi, const Vec3& wo, const Vec2& uv) const override {
        return nested_->pdf(wi, wo, uv);
    }
    [[nodiscard]] std::optional<BsdfSample> sample(const Vec3& wi, const Vec2& uv, Transport mode, double uLobe,
                                                   const Vec2& u) const override {
        return nested_->sample(wi, uv, mode, uLobe, u);
    }
    [[nodiscard]] std::optional<BsdfSample> deltaEval(const Vec3& wi, const Vec3& wo, const Vec2& uv,
                                                      Transport mode) const override {
        return nested_->deltaEval(wi, wo, uv, mode);
    }
    [[nodiscard]] Lobes lobes() const override { return nested_->lobes(); }
    [[nodiscard]] double roughness(const Vec2& uv) const override { return nested_->roughness(uv); }
    [[nodiscard]] std::optional<InterfaceEta> eta() const override { return nested_->eta(); }
    [[nodiscard]] std::string typeName() const override { return "bumpmap"; }

    [[nodiscard]] const Bsdf& nested() const { return *nested_; }
    [[nodiscard]] const std::shared_ptr<const Texture>& displacement() const { return displacement_; }

private:
    std::shared_ptr<const Texture> displacement_;
    std::shared_ptr<const Bsdf> nested_;
};

} // namespace lt
