// An orthonormal frame (s, t, n). The one frame convention of the project: local z is the normal,
// local x is s (the first tangent, along dp/du where the surface has one), local y is t = n x s.
#pragma once

#include "math/vec.h"

namespace lt {

struct Frame {
    Vec3 s{1, 0, 0}, t{0, 1, 0}, n{0, 0, 1};

    Frame() = default;
    Frame(const Vec3& s_, const Vec3& t_, const Vec3& n_) : s(s_), t(t_), n(n_) {}

    // A frame around a unit normal alone: Duff et al. 2017, "Building an Orthonormal Basis, Revisited"
    // (branchless, continuous except on one half-plane, exact for unit input).
    static Frame fromNormal(const Vec3& n) {
        const double sign = std::copysign(1.0, n.z);
        const double a = -1.0 / (sign + n.z);
        const double b = n.x * n.y * a;
        return {Vec3(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x), Vec3(b, sign + n.y * n.y * a, -n.y), n};
    }

    // A frame whose s follows a tangent direction (projected into the plane of n; Gram-Schmidt).
    static Frame fromNormalTangent(const Vec3& n, const Vec3& tangent) {
        Vec3 s = tangent - n * dot(n, tangent);
        const double len = length(s);
        if (!(len > 1e-12)) return fromNormal(n);
        s = s / len;
        return {s, cross(n, s), n};
    }

    [[nodiscard]] Vec3 toLocal(const Vec3& v) const { return {dot(v, s), dot(v, t), dot(v, n)}; }
    [[nodiscard]] Vec3 toWorld(const Vec3& v) const { return s * v.x + t * v.y + n * v.z; }
};

// The unit direction at polar angle theta (given by its cosine and sine, so that callers near theta = 0
// keep their precision) and azimuth phi around the unit `axis`.
inline Vec3 directionAround(const Vec3& axis, double cosTheta, double sinTheta, double phi) {
    return normalize(
        Frame::fromNormal(axis).toWorld(Vec3(sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta)));
}

// Spherical-coordinate helpers for directions expressed in a local frame (z = normal).
inline double cosTheta(const Vec3& w) { return w.z; }
inline double absCosTheta(const Vec3& w) { return std::abs(w.z); }
inline double cos2Theta(const Vec3& w) { return w.z * w.z; }
inline double sin2Theta(const Vec3& w) { return std::max(0.0, 1.0 - w.z * w.z); }
inline double sinTheta(const Vec3& w) { return std::sqrt(sin2Theta(w)); }
inline double tan2Theta(const Vec3& w) { return sin2Theta(w) / cos2Theta(w); }
inline bool sameHemisphere(const Vec3& a, const Vec3& b) { return a.z * b.z > 0; }

} // namespace lt
