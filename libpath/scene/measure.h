// Conversions between the densities of a point sampled on a surface: area on the surface versus solid
// angle at the point it is seen from (Veach thesis Eq. 8.10). The one place for this
// conversion; path vertices, emitters and the camera call it.
#pragma once

#include <cmath>

#include "math/vec.h"

namespace lt {

// Area density at p (surface normal n) -> solid-angle density of the direction from `from` toward p:
// p_w = p_A d^2 / |cos theta_p|. Zero when the direction grazes the surface (the area density cannot
// be expressed in solid angle there) or p coincides with `from`.
inline double pdfAreaToSolidAngle(double pdfArea, const Vec3& from, const Vec3& p, const Vec3& n) {
    const Vec3 v = p - from;
    const double dist2 = lengthSquared(v);
    const double absCos = std::abs(dot(n, v)) / std::sqrt(dist2);
    return dist2 > 0 && absCos > 0 ? pdfArea * dist2 / absCos : 0.0;
}

// Solid-angle density at `from` -> area density at p (normal n): p_A = p_w |cos theta_p| / d^2. A point
// that is not on a surface (n = 0: a pinhole, a point light) has no cosine: p = p_w / d^2, the density
// per unit area of a sphere around `from` (Veach thesis 8.2.2, pbrt-v3 Vertex::ConvertDensity).
inline double pdfSolidAngleToArea(double pdfSolidAngle, const Vec3& from, const Vec3& p, const Vec3& n) {
    const Vec3 v = p - from;
    const double dist2 = lengthSquared(v);
    if (!(dist2 > 0)) return 0.0;
    const double cosine = lengthSquared(n) > 0 ? std::abs(dot(n, v)) / std::sqrt(dist2) : 1.0;
    return pdfSolidAngle * cosine / dist2;
}

} // namespace lt
