#include "bsdf/conductor.h"

#include "bsdf/fresnel.h"
#include "util/error.h"

namespace lt {

void checkConductorParams(const std::string& plugin, const Spectrum& eta, const Spectrum& k, double extEta) {
    for (int c = 0; c < 3; ++c)
        if (!(eta[c] >= 0) || !(k[c] >= 0) || !std::isfinite(eta[c]) || !std::isfinite(k[c]))
            throw Error(plugin + ": eta and k must be non-negative and finite");
    if (!(extEta > 0) || !std::isfinite(extEta)) throw Error(plugin + ": extEta must be positive and finite");
}

Conductor::Conductor(ConductorParams params) : p_(std::move(params)) {
    checkConductorParams("conductor", p_.eta, p_.k, p_.extEta);
    if (!p_.specularReflectance) throw Error("conductor: null texture");
    p_.eta /= p_.extEta;
    p_.k /= p_.extEta;
}

std::optional<BsdfSample> Conductor::sample(const Vec3& wi, const Vec2& uv, Transport, double, const Vec2&) const {
    if (wi.z <= 0) return std::nullopt;
    BsdfSample s;
    s.wo = Vec3(-wi.x, -wi.y, wi.z);
    s.pdf = 1;
    s.weight = p_.specularReflectance->eval(uv) * fresnelConductor(wi.z, p_.eta, p_.k);
    s.lobe = LobeDelta | LobeReflection;
    return s;
}

std::optional<BsdfSample> Conductor::deltaEval(const Vec3& wi, const Vec3& wo, const Vec2& uv, Transport mode) const {
    auto s = sample(wi, uv, mode, 0, {});
    if (s && length(s->wo - wo) < DeltaDirectionTolerance) return s;
    return std::nullopt;
}

} // namespace lt
