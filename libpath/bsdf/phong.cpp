#include "bsdf/phong.h"

#include <cmath>

#include "math/constants.h"
#include "util/error.h"
#include "math/frame.h"

namespace lt {

namespace {

// cos alpha: wo against wi's mirror direction about the normal (z).
double cosToMirror(const Vec3& wi, const Vec3& wo) { return -wi.x * wo.x - wi.y * wo.y + wi.z * wo.z; }

} // namespace

Phong::Phong(PhongParams params) : GlossyDiffuseBsdf(params.reflectances), exponent_(std::move(params.exponent)) {
    if (!exponent_) throw Error("phong: null exponent texture");
    const Spectrum top = exponent_->maximum();
    if (!top.isFinite() || (exponent_->isConstant() && !(exponent_->scalar({}) >= 0)))
        throw Error("phong: exponent must be finite and non-negative");
}

double Phong::roughness(const Vec2& uv) const { return std::sqrt(2 / (exponent(uv) + 2)); }

double Phong::glossy(const Vec3& wi, const Vec3& wo, const Vec2& uv) const {
    const double c = cosToMirror(wi, wo), n = exponent(uv);
    return c > 0 ? (n + 2) * InvTwoPi * std::pow(c, n) : 0.0;
}

double Phong::glossyPdf(const Vec3& wi, const Vec3& wo, const Vec2& uv) const {
    const double c = cosToMirror(wi, wo), n = exponent(uv);
    return c > 0 ? (n + 1) * InvTwoPi * std::pow(c, n) : 0.0;
}

std::optional<Vec3> Phong::sampleGlossy(const Vec3& wi, const Vec2& uv, const Vec2& u) const {
    // cos alpha = u^(1/(n+1)) inverts the lobe's cumulative distribution in cos alpha.
    const double cosAlpha = std::pow(u.y, 1 / (exponent(uv) + 1));
    const double sinAlpha = std::sqrt(std::max(0.0, 1 - cosAlpha * cosAlpha));
    return directionAround(Vec3(-wi.x, -wi.y, wi.z), cosAlpha, sinAlpha, TwoPi * u.x);
}

} // namespace lt
