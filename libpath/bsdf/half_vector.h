// The generalized half vector and its Jacobian: the one place for this math. Microfacet
// BSDFs, the manifold constraints and the half-vector (HSLT) mutations all call these.
//
// Convention (HSLT App. A; ME Eq. 7; Walter et al. 2007 Eq. 16): i and o are unit
// vectors pointing AWAY from the vertex, eta = eta_o / eta_i (the index on o's side over the index on
// i's side) for transmission and eta = 1 for reflection. h = (i + eta o) / |i + eta o|, oriented into
// the hemisphere of the normal n.
#pragma once

#include <optional>

#include "math/numeric.h"
#include "math/vec.h"

namespace lt {

// i + eta o without normalization or orientation. At an index-matched interface (eta = 1,
// transmission) it vanishes at the solution, so the manifold constraint uses it unnormalized
// (normalizing a vector that vanishes would divide by zero).
[[nodiscard]] inline Vec3 halfVectorUnnormalized(const Vec3& i, const Vec3& o, double eta) { return i + eta * o; }

// The normalized generalized half vector oriented to the side of n (default: the local +z); nothing
// when i + eta o vanishes (index-matched straight-through transmission) or is not finite.
[[nodiscard]] inline std::optional<Vec3> halfVector(const Vec3& i, const Vec3& o, double eta,
                                                    const Vec3& n = Vec3(0, 0, 1)) {
    const Vec3 H = halfVectorUnnormalized(i, o, eta);
    const double len = length(H);
    if (!(len > 1e-12) || !std::isfinite(len)) return std::nullopt;
    const Vec3 h = H / len;
    return dot(h, n) < 0 ? -h : h;
}

// |d omega_h / d omega_o| = eta^2 |h.o| / (h.i + eta h.o)^2 (HSLT Eq. 10, Walter 2007 Eq. 16-17); for
// reflection (eta = 1, h.i = h.o) this is 1 / (4 |h.o|). Returns 0, never NaN or Inf, when the
// denominator vanishes (grazing or index-matched configurations).
[[nodiscard]] inline double halfVectorJacobian(const Vec3& h, const Vec3& i, const Vec3& o, double eta) {
    const double denom = sqr(dot(h, i) + eta * dot(h, o));
    if (!(denom > 0)) return 0;
    const double J = eta * eta * std::abs(dot(h, o)) / denom;
    return std::isfinite(J) ? J : 0.0;
}

// Snell refraction of w (pointing away from the surface, on either side of n) through the plane with
// normal n. eta = eta_t / eta_w: the index of the side being entered over the index of w's side.
// Returns the transmitted direction (pointing away from the surface on the other side), or nothing on
// total internal reflection.
[[nodiscard]] inline std::optional<Vec3> refract(const Vec3& w, const Vec3& n, double eta) {
    const Vec3 nn = dot(w, n) < 0 ? -n : n;
    const double cosI = dot(w, nn);
    const double sin2T = (1 - cosI * cosI) / (eta * eta);
    if (sin2T >= 1) return std::nullopt;
    const double cosT = std::sqrt(1 - sin2T);
    return -w / eta + (cosI / eta - cosT) * nn;
}

} // namespace lt
