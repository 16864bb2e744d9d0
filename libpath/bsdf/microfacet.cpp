#include "bsdf/microfacet.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "math/constants.h"
#include "math/numeric.h"

namespace lt {

namespace {

constexpr double MinAlpha = 1e-4;
const double InvSqrtPi = 1.0 / std::sqrt(Pi);

// Inverse error function in double: Giles 2010 ("Approximating the erfinv function", GPU Computing
// Gems) single-precision polynomial as the start, then two Newton steps on std::erf, which bring it to
// full double precision. |y| is clamped below 1 so the result stays finite (|x| <= ~5.9).
double erfInv(double y) {
    y = std::clamp(y, -1 + 1e-16, 1 - 1e-16);
    double w = -std::log((1 - y) * (1 + y)), p;
    if (w < 5) {
        w -= 2.5;
        p = 2.81022636e-08;
        p = 3.43273939e-07 + p * w;
        p = -3.5233877e-06 + p * w;
        p = -4.39150654e-06 + p * w;
        p = 0.00021858087 + p * w;
        p = -0.00125372503 + p * w;
        p = -0.00417768164 + p * w;
        p = 0.246640727 + p * w;
        p = 1.50140941 + p * w;
    } else {
        w = std::sqrt(w) - 3;
        p = -0.000200214257;
        p = 0.000100950558 + p * w;
        p = 0.00134934322 + p * w;
        p = -0.00367342844 + p * w;
        p = 0.00573950773 + p * w;
        p = -0.0076224613 + p * w;
        p = 0.00943887047 + p * w;
        p = 1.00167406 + p * w;
        p = 2.83297682 + p * w;
    }
    double x = p * y;
    for (int it = 0; it < 2; ++it) {
        const double dens = 2 * InvSqrtPi * std::exp(-x * x);
        if (!(dens > 0)) break;
        x -= (std::erf(x) - y) / dens;
    }
    return x;
}

} // namespace

MicrofacetDistribution::MicrofacetDistribution(MicrofacetType type, double alphaU, double alphaV)
    : type_(type), alphaU_(std::max(alphaU, MinAlpha)), alphaV_(std::max(alphaV, MinAlpha)) {}

double MicrofacetDistribution::beckmannEquivalentAlpha() const {
    const double a = std::min(alphaU_, alphaV_);
    return type_ == MicrofacetType::GGX ? a / std::sqrt(2.0) : a;
}

double MicrofacetDistribution::D(const Vec3& m) const {
    if (m.z <= 0) return 0;
    const double c2 = m.z * m.z;
    const double t = sqr(m.x / alphaU_) + sqr(m.y / alphaV_);
    if (type_ == MicrofacetType::Beckmann) {
        // Walter 2007 Eq. 25 with the anisotropic slope norm: exp(-tan^2 / alpha^2) / (pi alpha^2 cos^4).
        return std::exp(-t / c2) / (Pi * alphaU_ * alphaV_ * c2 * c2);
    }
    // Walter 2007 Eq. 33 rewritten as 1 / (pi au av (cos^2 + t)^2): no tan^2 that blows up at m.z -> 0.
    return 1 / (Pi * alphaU_ * alphaV_ * sqr(c2 + t));
}

double MicrofacetDistribution::smithLambda(const Vec3& v) const {
    // alpha_v^2 tan^2(theta_v) with the roughness projected on v's azimuth (Heitz 2014 Eq. 80).
    const double t2 = (sqr(v.x * alphaU_) + sqr(v.y * alphaV_)) / (v.z * v.z);
    if (!(t2 > 0)) return 0;
    if (!std::isfinite(t2)) return std::numeric_limits<double>::infinity();
    if (type_ == MicrofacetType::Beckmann) {
        // Lambda = (erf(a) - 1) / 2 + exp(-a^2) / (2 a sqrt(pi)), a = 1 / (alpha tan): exact, so that the
        // visible-normal density integrates to one.
        const double a = 1 / std::sqrt(t2);
        return std::max(0.0, 0.5 * (-std::erfc(a) + std::exp(-a * a) * InvSqrtPi / a));
    }
    // (sqrt(1 + t2) - 1) / 2 written without cancellation for small t2.
    return t2 / (2 * (1 + std::sqrt(1 + t2)));
}

double MicrofacetDistribution::G1(const Vec3& v, const Vec3& m) const {
    if (dot(v, m) * v.z <= 0) return 0;
    return 1 / (1 + smithLambda(v));
}

double MicrofacetDistribution::G(const Vec3& i, const Vec3& o, const Vec3& m) const { return G1(i, m) * G1(o, m); }

Vec2 MicrofacetDistribution::sampleVisibleSlopesBeckmann11(double cosTheta, const Vec2& u) const {
    // Slopes of the unit Beckmann distribution are independent normals of variance 1/2; the visible
    // ones are weighted by the projected area (cot(theta) - x) sin(theta), which only involves x. The
    // CDF of x times 2 tan(theta) is C(x) = 1 + erf(x) + tan(theta) exp(-x^2) / sqrt(pi) on
    // x < cot(theta). Solve C = u C(cot) for b = erf(x), where C is nearly linear (dC/db = 1 - x tan).
    const double sinTheta = safeSqrt(1 - cosTheta * cosTheta);
    const double y = erfInv(2 * u.y - 1);
    if (sinTheta < 1e-9) return {erfInv(2 * u.x - 1), y};
    const double tanTheta = sinTheta / cosTheta, cotTheta = cosTheta / sinTheta;
    const auto C = [tanTheta](double b, double x) { return 1 + b + tanTheta * std::exp(-x * x) * InvSqrtPi; };
    double lo = -1, hi = std::erf(cotTheta);
    const double target = u.x * C(hi, cotTheta);
    double b = lo + u.x * (hi - lo);
    double x = erfInv(b);
    for (int it = 0; it < 60; ++it) {
        const double value = C(b, x) - target;
        if (std::abs(value) < 1e-13 * target) break;
        (value > 0 ? hi : lo) = b;
        const double deriv = 1 - x * tanTheta;
        double next = b - value / deriv;
        // Newton inside the bracket, bisection otherwise (also catches NaN).
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        if (next == b) break;
        b = next;
        x = erfInv(b);
    }
    return {std::min(x, cotTheta), y};
}

Vec3 MicrofacetDistribution::sampleVisible(const Vec3& v, const Vec2& u) const {
    const Vec3 w = v.z < 0 ? -v : v;
    // Stretch to the unit-roughness configuration (Heitz & d'Eon 2014, Heitz 2018 Sec. 2).
    const Vec3 ws = normalize(Vec3(alphaU_ * w.x, alphaV_ * w.y, w.z));
    if (type_ == MicrofacetType::GGX) {
        // Heitz 2018, Listing 1: sample the projected hemisphere of the stretched direction.
        const double lensq = ws.x * ws.x + ws.y * ws.y;
        const Vec3 T1 = lensq > 0 ? Vec3(-ws.y, ws.x, 0) / std::sqrt(lensq) : Vec3(1, 0, 0);
        const Vec3 T2 = cross(ws, T1);
        const double r = std::sqrt(u.x), phi = TwoPi * u.y;
        const double t1 = r * std::cos(phi);
        const double s = 0.5 * (1 + ws.z);
        const double t2 = (1 - s) * safeSqrt(1 - t1 * t1) + s * r * std::sin(phi);
        const Vec3 nh = t1 * T1 + t2 * T2 + safeSqrt(1 - t1 * t1 - t2 * t2) * ws;
        return normalize(Vec3(alphaU_ * nh.x, alphaV_ * nh.y, std::max(0.0, nh.z)));
    }
    const double sinTheta = std::sqrt(ws.x * ws.x + ws.y * ws.y);
    const double cosPhi = sinTheta > 0 ? ws.x / sinTheta : 1, sinPhi = sinTheta > 0 ? ws.y / sinTheta : 0;
    const Vec2 s = sampleVisibleSlopesBeckmann11(ws.z, u);
    // Rotate back to the azimuth of the incident direction, unstretch, and turn the slope into a normal.
    const double sx = alphaU_ * (cosPhi * s.x - sinPhi * s.y);
    const double sy = alphaV_ * (sinPhi * s.x + cosPhi * s.y);
    return normalize(Vec3(-sx, -sy, 1));
}

double MicrofacetDistribution::pdfVisible(const Vec3& v, const Vec3& m) const {
    const Vec3 w = v.z < 0 ? -v : v;
    if (w.z <= 0) return 0;
    const double wm = dot(w, m);
    if (wm <= 0) return 0;
    // Heitz 2014 Eq. 2: D_w(m) = G1(w, m) <w, m> D(m) / cos(theta_w).
    return G1(w, m) * wm * D(m) / w.z;
}

} // namespace lt
