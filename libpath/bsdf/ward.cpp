#include "bsdf/ward.h"

#include <algorithm>
#include <cmath>

#include "math/constants.h"
#include "math/error.h"
#include "math/frame.h"

namespace lt {

Ward::Ward(WardParams params) : GlossyDiffuseBsdf(params.reflectances), p_(params) {
    if (!(p_.alphaU > 0) || !(p_.alphaV > 0) || !std::isfinite(p_.alphaU) || !std::isfinite(p_.alphaV))
        throw Error("ward: alpha must be positive and finite");
}

double Ward::roughness(const Vec2&) const { return std::min(p_.alphaU, p_.alphaV); }

double Ward::slopeFalloff(const Vec3& h) const {
    const double x = h.x / p_.alphaU, y = h.y / p_.alphaV;
    return std::exp(-(x * x + y * y) / (h.z * h.z));
}

double Ward::glossy(const Vec3& wi, const Vec3& wo) const {
    const Vec3 h = wi + wo;
    if (!(h.z > 0)) return 0;
    const double a = p_.alphaU * p_.alphaV;
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
    const double f = norm * slopeFalloff(h);
    return f > 1e-10 ? f : 0.0;
}

double Ward::glossyPdf(const Vec3& wi, const Vec3& wo) const {
    const Vec3 h = normalize(wi + wo);
    if (!(h.z > 0)) return 0;
    const double pdfH = slopeFalloff(h) / (Pi * p_.alphaU * p_.alphaV * h.z * h.z * h.z);
    return pdfH / (4 * dot(wi, h));
}

std::optional<Vec3> Ward::sampleGlossy(const Vec3& wi, const Vec2& u) const {
    if (!(u.x > 0)) return std::nullopt;
    // tan phi_h = (alpha_v / alpha_u) tan(2 pi u_y), in the quadrant of 2 pi u_y; then tan^2 theta_h from
    // the exponential's inverse cumulative distribution at that azimuth.
    const double phi = std::atan2(p_.alphaV * std::sin(TwoPi * u.y), p_.alphaU * std::cos(TwoPi * u.y));
    const double c = std::cos(phi), s = std::sin(phi);
    const double tan2 = -std::log(u.x) / (c * c / (p_.alphaU * p_.alphaU) + s * s / (p_.alphaV * p_.alphaV));
    const double cosTheta = 1 / std::sqrt(1 + tan2), sinTheta = std::sqrt(tan2) * cosTheta;
    const Vec3 h(sinTheta * c, sinTheta * s, cosTheta);
    return reflect(wi, h);
}

} // namespace lt
