#include "bsdf/dielectric.h"

#include <cmath>

#include "bsdf/fresnel.h"
#include "bsdf/half_vector.h"
#include "bsdf/ior_presets.h"
#include "util/error.h"

namespace lt {

Dielectric::Dielectric(DielectricParams params) : p_(std::move(params)), eta_(p_.relativeEta("dielectric")) {}

std::optional<BsdfSample> Dielectric::lobeSample(const Vec3& wi, const Vec2& uv, Transport mode, bool reflect) const {
    if (wi.z == 0) return std::nullopt;
    const double F = fresnelDielectric(wi.z, eta_);
    BsdfSample s;
    if (reflect) {
        if (!(F > 0)) return std::nullopt;
        s.wo = Vec3(-wi.x, -wi.y, wi.z);
        s.pdf = F;
        s.weight = p_.specularReflectance->eval(uv); // F / F
        s.lobe = LobeDelta | LobeReflection;
        s.eta = 1;
        return s;
    }
    const double etaRel = wi.z > 0 ? eta_ : 1 / eta_; // eta_wo / eta_wi
    const auto wt = refract(wi, Vec3(0, 0, 1), etaRel);
    if (!(F < 1) || !wt) return std::nullopt;
    s.wo = *wt;
    s.pdf = 1 - F;
    s.weight = p_.specularTransmittance->eval(uv); // (1 - F) / (1 - F)
    // Radiance is compressed into the smaller solid angle of the denser side (Veach thesis 5.2): in
    // Radiance mode the refracted value carries (eta_wi / eta_wo)^2, in Importance mode nothing (bsdf.h).
    if (mode == Transport::Radiance) s.weight *= 1 / (etaRel * etaRel);
    s.lobe = LobeDelta | LobeTransmission;
    s.eta = etaRel;
    return s;
}

std::optional<BsdfSample> Dielectric::sample(const Vec3& wi, const Vec2& uv, Transport mode, double uLobe,
                                             const Vec2&) const {
    if (wi.z == 0) return std::nullopt;
    const bool reflect = uLobe < fresnelDielectric(wi.z, eta_);
    return lobeSample(wi, uv, mode, reflect);
}

std::optional<BsdfSample> Dielectric::deltaEval(const Vec3& wi, const Vec3& wo, const Vec2& uv, Transport mode) const {
    for (const bool reflect : {true, false}) {
        auto s = lobeSample(wi, uv, mode, reflect);
        if (s && length(s->wo - wo) < DeltaDirectionTolerance) return s;
    }
    return std::nullopt;
}

} // namespace lt
