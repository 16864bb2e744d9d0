#include "bsdf/ward.h"

#include <algorithm>
#include <cmath>

#include "math/constants.h"
#include "util/error.h"
#include "math/frame.h"

namespace lt {

Ward::Ward(WardParams params) : GlossyDiffuseBsdf(params.reflectances), p_(params) {
    if (!p_.alphaU || !p_.alphaV) throw Error("ward: null alpha texture");
    for (const auto* t : {p_.alphaU.get(), p_.alphaV.get()})
        if (!t->maximum().isFinite() || (t->isConstant() && !(t->scalar({}) > 0)))
            throw Error("ward: alpha must be positive and finite");
}

Vec2 Ward::alphas(const Vec2& uv) const {
    return {std::max(1e-4, p_.alphaU->scalar(uv)), std::max(1e-4, p_.alphaV->scalar(uv))};
}

double Ward::roughness(const Vec2& uv) const {
    const Vec2 a = alphas(uv);
    return std::min(a.x, a.y);
}

double Ward::slopeFalloff(const Vec3& h, const Vec2& alpha) {
    const double x = h.x / alpha.x, y = h.y / alpha.y;
    return std::exp(-(x * x + y * y) / (h.z * h.z));
}

double Ward::glossy(const Vec3& wi, const Vec3& wo, const Vec2& uv) const {
    const Vec3 h = wi + wo;
    if (!(h.z > 0)) return 0;
    const Vec2 alpha = alphas(uv);
    const double a = alpha.x * alpha.y;
    double norm = 0;
    switch (p_.variant) {
    case WardVariant::Ward:
        norm = 1 / (4 * Pi * a * std::sqrt(wi.z * wo.z));
        break;
    case WardVariant::WardDuer:
        norm = 1 / (4 * Pi * a * wi.z * wo.z);
        break;
    case WardVariant::Balanced:
        norm = dot(h, h) / (Pi * a * std::pow(h.z, 4));
        break;
    }
    const double f = norm * slopeFalloff(h, alpha);
    return f > 1e-10 ? f : 0.0;
}

double Ward::glossyPdf(const Vec3& wi, const Vec3& wo, const Vec2& uv) const {
    const Vec3 h = normalize(wi + wo);
    if (!(h.z > 0)) return 0;
    const Vec2 alpha = alphas(uv);
    const double pdfH = slopeFalloff(h, alpha) / (Pi * alpha.x * alpha.y * h.z * h.z * h.z);
    return pdfH / (4 * dot(wi, h));
}

std::optional<Vec3> Ward::sampleGlossy(const Vec3& wi, const Vec2& uv, const Vec2& u) const {
    if (!(u.x > 0)) return std::nullopt;
    const Vec2 alpha = alphas(uv);
    // tan phi_h = (alpha_v / alpha_u) tan(2 pi u_y), in the quadrant of 2 pi u_y; then tan^2 theta_h from
    // the exponential's inverse cumulative distribution at that azimuth.
    const double phi = std::atan2(alpha.y * std::sin(TwoPi * u.y), alpha.x * std::cos(TwoPi * u.y));
    const double c = std::cos(phi), s = std::sin(phi);
    const double tan2 = -std::log(u.x) / (c * c / (alpha.x * alpha.x) + s * s / (alpha.y * alpha.y));
    const double cosTheta = 1 / std::sqrt(1 + tan2), sinTheta = std::sqrt(tan2) * cosTheta;
    const Vec3 h(sinTheta * c, sinTheta * s, cosTheta);
    return reflect(wi, h);
}

} // namespace lt
