// Warps from the unit square to sampling domains, each with its density in the domain's own measure.
// The one place these mappings live: BSDFs, lights, the camera and the tests all call these.
#pragma once

#include "math/constants.h"
#include "math/numeric.h"
#include "math/vec.h"

namespace lt::warp {

// Shirley-Chiu concentric map of [0,1)^2 to the unit disk (area-preserving up to a constant, low
// distortion, continuous).
inline Vec2 squareToUniformDiskConcentric(const Vec2& u) {
    const double ox = 2 * u.x - 1, oy = 2 * u.y - 1;
    if (ox == 0 && oy == 0) return {0, 0};
    double r, phi;
    if (std::abs(ox) > std::abs(oy)) {
        r = ox;
        phi = (Pi / 4) * (oy / ox);
    } else {
        r = oy;
        phi = (Pi / 2) - (Pi / 4) * (ox / oy);
    }
    return {r * std::cos(phi), r * std::sin(phi)};
}
inline double squareToUniformDiskPdf() { return InvPi; }

// Cosine-weighted hemisphere around +z (Malley's method); density in solid angle.
inline Vec3 squareToCosineHemisphere(const Vec2& u) {
    const Vec2 d = squareToUniformDiskConcentric(u);
    return {d.x, d.y, safeSqrt(1 - d.x * d.x - d.y * d.y)};
}
inline double squareToCosineHemispherePdf(const Vec3& w) { return w.z > 0 ? w.z * InvPi : 0.0; }

inline Vec3 squareToUniformSphere(const Vec2& u) {
    const double z = 1 - 2 * u.x;
    const double r = safeSqrt(1 - z * z);
    const double phi = TwoPi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), z};
}
inline double squareToUniformSpherePdf() { return InvFourPi; }

inline Vec3 squareToUniformHemisphere(const Vec2& u) {
    const double z = u.x;
    const double r = safeSqrt(1 - z * z);
    const double phi = TwoPi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), z};
}
inline double squareToUniformHemispherePdf(const Vec3& w) { return w.z > 0 ? InvTwoPi : 0.0; }

// Uniform directions in the cone of half-angle acos(cosThetaMax) around +z.
inline Vec3 squareToUniformCone(const Vec2& u, double cosThetaMax) {
    const double z = 1 - u.x * (1 - cosThetaMax);
    const double r = safeSqrt(1 - z * z);
    const double phi = TwoPi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), z};
}
inline double squareToUniformConePdf(double cosThetaMax) { return 1.0 / (TwoPi * (1 - cosThetaMax)); }

// The same cone warp parameterized by 1 - cos(thetaMax). For the tiny cones that small, distant spheres
// subtend (radius 1e-3 seen from 1e5), cos(thetaMax) rounds to 1 in double while 1 - cos(thetaMax),
// computed by the caller as sin^2(thetaMax) / (1 + cos(thetaMax)), keeps full precision; sin(theta) is
// formed from 1 - cos(theta) without cancellation, so x^2 + y^2 of the result is an accurate sin^2(theta).
inline Vec3 squareToUniformConeNarrow(const Vec2& u, double oneMinusCosThetaMax) {
    const double w = u.x * oneMinusCosThetaMax;   // 1 - cos(theta)
    const double r = safeSqrt(w * (2 - w));
    const double phi = TwoPi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), 1 - w};
}
inline double squareToUniformConeNarrowPdf(double oneMinusCosThetaMax) { return 1.0 / (TwoPi * oneMinusCosThetaMax); }

// Uniform barycentrics (b1, b2) on a triangle; b0 = 1 - b1 - b2.
inline Vec2 squareToUniformTriangle(const Vec2& u) {
    const double su = std::sqrt(u.x);
    return {1 - su, u.y * su};
}

} // namespace lt::warp
