#include "bsdf/diffuse.h"

#include <limits>

#include "util/error.h"
#include "math/frame.h"
#include "math/warp.h"

namespace lt {

Diffuse::Diffuse(DiffuseParams params) : p_(std::move(params)) {
    if (!p_.reflectance) throw Error("diffuse: reflectance texture is null");
}

Spectrum Diffuse::eval(const Vec3& wi, const Vec3& wo, const Vec2& uv, Transport) const {
    if (cosTheta(wi) <= 0 || cosTheta(wo) <= 0) return {};
    return p_.reflectance->eval(uv) * InvPi;
}

double Diffuse::pdf(const Vec3& wi, const Vec3& wo, const Vec2&) const {
    if (cosTheta(wi) <= 0) return 0;
    return warp::squareToCosineHemispherePdf(wo);
}

std::optional<BsdfSample> Diffuse::sample(const Vec3& wi, const Vec2& uv, Transport, double, const Vec2& u) const {
    if (cosTheta(wi) <= 0) return std::nullopt;
    BsdfSample s;
    s.wo = warp::squareToCosineHemisphere(u);
    s.pdf = warp::squareToCosineHemispherePdf(s.wo);
    if (!(s.pdf > 0)) return std::nullopt;
    s.weight = p_.reflectance->eval(uv); // (R / pi) cos / (cos / pi)
    s.lobe = LobeDiffuse | LobeReflection;
    return s;
}

double Diffuse::roughness(const Vec2&) const { return std::numeric_limits<double>::infinity(); }

} // namespace lt
