// Mitsuba's `twosided`: makes a one-sided reflecting BSDF reflect on both sides. On the back side
// (wi.z < 0) both directions are mirrored through the tangent plane (z -> -z) so the nested BSDF sees
// its front, as Mitsuba 0.5 twosided.cpp does; an optional second BSDF serves the back side.
#pragma once

#include <memory>

#include "bsdf/bsdf.h"

namespace lt {

struct TwoSidedParams {
    std::shared_ptr<const Bsdf> front;
    std::shared_ptr<const Bsdf> back; // null: the front BSDF on both sides
};

class TwoSided final : public Bsdf {
public:
    // Throws lt::Error if front is null or a nested BSDF transmits (Mitsuba refuses these too: the
    // mirroring would turn transmission into nonsense).
    explicit TwoSided(TwoSidedParams params);

    [[nodiscard]] Spectrum eval(const Vec3& wi, const Vec3& wo, const Vec2& uv, Transport mode) const override;
    [[nodiscard]] double pdf(const Vec3& wi, const Vec3& wo, const Vec2& uv) const override;
    [[nodiscard]] std::optional<BsdfSample> sample(const Vec3& wi, const Vec2& uv, Transport mode, double uLobe,
                                                   const Vec2& u) const override;
    [[nodiscard]] std::optional<BsdfSample> deltaEval(const Vec3& wi, const Vec3& wo, const Vec2& uv,
                                                      Transport mode) const override;
    [[nodiscard]] Lobes lobes() const override;
    // The smaller of the two sides' roughness (the sharper lobe decides specular treatment).
    [[nodiscard]] double roughness(const Vec2& uv) const override;
    [[nodiscard]] std::string typeName() const override { return "twosided"; }
    // The nested BSDF of the front side (for reports such as lt-inspect's "twosided(diffuse)").
    [[nodiscard]] const Bsdf& frontBsdf() const { return *p_.front; }

private:
    // The BSDF serving wi's side.
    [[nodiscard]] const Bsdf& side(const Vec3& wi) const { return wi.z < 0 ? *p_.back : *p_.front; }
    TwoSidedParams p_;
};

} // namespace lt
