// A vertex of a specular chain in the local chart the manifold machinery works in, and THE frame
// convention of libpath/manifold (written down here once; ME section 3.3):
//
// * Chart. The parameterization tangents dp/du, dp/dv orthonormalized by Gram-Schmidt (u along dp/du,
//   v the rest of dp/dv), with dn/du, dn/dv (derivatives of the normalized shading normal n)
//   transformed by the same linear map (ME footnote 2; Mitsuba's init()). A vertex moves in its chart,
//   x(a, b) = x + a u + b v, so chart area is surface area and Eq. 9 needs no extra determinants.
// * Tangent frame. T(x) = [s t] with s = u - (u.n) n, t = v - (v.n) n: the chart tangents projected
//   into the shading plane (unit only where n equals the geometric normal). The frame field around x is
//   the same u, v projected onto the shading normal at the moved point; its derivative is the
//   frame-rotation (curvature) part of the B block. On the specular manifold (c = 0) that part does not
//   depend on the choice of field; off it (offset vertices, HSLT's h-perp) it does, so every user of
//   the constraint (Jacobian, tangent maps, Newton solve, proposals) must use this same field (mixing
//   two frame fields biases the chain without any visible error).
// * Constraint. c = T^T h = (s.h, t.h) with h the generalized half vector (bsdf/half_vector.h),
//   oriented to the side of n; specular_constraint.h.
#pragma once

#include <optional>

#include "scene/interaction.h"

namespace lt {

enum class Scatter : uint8_t { Reflection, Transmission };

struct ManifoldVertex {
    Vec3 p;          // position
    Vec3 ng;         // unit geometric normal (zero for a point without surface: pinhole, point light)
    Vec3 n;          // unit shading normal
    Vec3 dpdu, dpdv; // orthonormal chart of the tangent plane
    Vec3 dndu, dndv; // derivatives of the shading normal along the chart
    int shape = -1;  // Scene::shapes index (-1: no surface)
    uint32_t prim = 0;
    Vec2 coords; // as SurfaceInteraction::coords
    double magnitude = 0;

    // Interior (specular or offset) vertices only.
    Scatter scatter = Scatter::Reflection;
    double eta = 1; // eta_o / eta_i of the generalized half vector (1 for reflection)
    Vec2 offset;    // constraint value held by walks: 0 if specular, the microfacet normal's o_i (ME Eq. 11)

    [[nodiscard]] bool onSurface() const { return lengthSquared(ng) > 0; }
    [[nodiscard]] RayEndpoint endpoint() const { return {p, ng, magnitude}; }
    // The tangent frame T(x) = [s t] of the convention above.
    [[nodiscard]] Vec3 s() const { return dpdu - n * dot(dpdu, n); }
    [[nodiscard]] Vec3 t() const { return dpdv - n * dot(dpdv, n); }
    // A world direction in frame coordinates: T^T w.
    [[nodiscard]] Vec2 frameCoordinates(const Vec3& w) const { return {dot(s(), w), dot(t(), w)}; }
    // Index-matched transmission: the half vector vanishes at the solution and is used unnormalized
    // (normalizing it would divide by zero).
    [[nodiscard]] bool indexMatched() const { return scatter == Scatter::Transmission && eta == 1; }
};

// A surface point (as Shape::surfaceAt gives it) with its chart orthonormalized (the convention
// above). Nothing when dp/du and dp/dv are degenerate (parallel or zero).
[[nodiscard]] std::optional<ManifoldVertex> manifoldVertex(const SurfaceInteraction& si);
// A point without surface (pinhole, point light): position only, with the chart of the plane
// perpendicular to `axis` so that chart coordinates exist; n = axis, ng = 0, no curvature.
[[nodiscard]] ManifoldVertex pointVertex(const Vec3& p, const Vec3& axis);
// A point of a plane with unit normal `normal` (flat chart, no curvature): the virtual plane of the
// walk's last vertex.
[[nodiscard]] ManifoldVertex planeVertex(const Vec3& p, const Vec3& normal);

// The unit microfacet normal m on n's side whose frame coordinates T^T m equal `offset` (T is not
// orthonormal in general: solve the 2x2 Gram system); nothing when no unit vector has them.
[[nodiscard]] std::optional<Vec3> microfacetNormal(const ManifoldVertex& v, const Vec2& offset);

} // namespace lt
