#include "bsdf/thindielectric.h"

#include <cmath>

#include "bsdf/fresnel.h"
#include "bsdf/ior_presets.h"
#include "util/error.h"
#include "math/numeric.h"

namespace lt {

ThinDielectric::ThinDielectric(DielectricParams params)
    : p_(std::move(params)), eta_(p_.relativeEta("thindielectric")) {}

double ThinDielectric::slabReflectance(const Vec3& wi) const {
    const double R = fresnelDielectric(std::abs(wi.z), eta_);
    // Geometric series of the bounces between the two faces: R + T^2 R (1 + R^2 + R^4 + ...).
    return R < 1 ? R + sqr(1 - R) * R / (1 - R * R) : 1.0;
}

std::optional<BsdfSample> ThinDielectric::lobeSample(const Vec3& wi, const Vec2& uv, bool reflect) const {
    if (wi.z == 0) return std::nullopt;
    const double R = slabReflectance(wi);
    BsdfSample s;
    s.eta = 1;
    if (reflect) {
        if (!(R > 0)) return std::nullopt;
        s.wo = Vec3(-wi.x, -wi.y, wi.z);
        s.pdf = R;
        s.weight = p_.specularReflectance->eval(uv);
        s.lobe = LobeDelta | LobeReflection;
    } else {
        if (!(R < 1)) return std::nullopt;
        s.wo = -wi;
        s.pdf = 1 - R;
        // Leaving into the same medium: no (eta_wi / eta_wo)^2 factor in either transport mode.
        s.weight = p_.specularTransmittance->eval(uv);
        s.lobe = LobeDelta | LobeTransmission;
    }
    return s;
}

std::optional<BsdfSample> ThinDielectric::sample(const Vec3& wi, const Vec2& uv, Transport, double uLobe,
                                                 const Vec2&) const {
    if (wi.z == 0) return std::nullopt;
    return lobeSample(wi, uv, uLobe < slabReflectance(wi));
}

std::optional<BsdfSample> ThinDielectric::deltaEval(const Vec3& wi, const Vec3& wo, const Vec2& uv, Transport) const {
    for (const bool reflect : {true, false}) {
        auto s = lobeSample(wi, uv, reflect);
        if (s && length(s->wo - wo) < DeltaDirectionTolerance) return s;
    }
    return std::nullopt;
}

} // namespace lt
