// A vertex of a specular chain in the local chart the manifold machinery works in, and THE frame
// convention of libpath/manifold (written down here once; ME section 3.3):
//
// * Chart. The parameterization tangents dp/du, dp/dv orthonormalized by Gram-Schmidt (u along dp/du,
//   v the rest of dp/dv), with dn/du, dn/dv (derivatives of the normalized shading normal n)
//   transformed by the same linear map (ME footnote 2; Mitsuba's init()). A vertex moves in its chart,
//   x(a, b) = x + a u + b v, so chart area is surface area and Eq. 9 needs no extra determinants.
// * Tangent frame. T(x) = [s t] with s = a - (a.n) n, t = b - (b.n) n: two frame generators a, b
//   projected into the shading plane (unit only where n is perpendicular to a and b). The generators are
//   the two world axes other than the dominant axis of the geometric normal: a function of the point
//   alone, constant over each triangle (its geometric normal is) and over each of the six cube-map
//   regions of a sphere. |s x t| = |n.e| (e the dominant axis of the geometric normal, n the shading
//   normal) is at least 1/sqrt 3 where n is the geometric normal; a shading normal tilted far from it
//   (35 degrees and more) can make the frame singular there, and walks through such a vertex fail. Within a region the
//   field's derivative is exactly the rotation of the shading normal, the frame-rotation part of the B block. On the
//   specular manifold (c = 0) that part does not depend on the choice of field; off it (offset vertices, HSLT's h-perp)
//   it does, so every user of the constraint (Jacobian, tangent maps, Newton solve, proposals, densities) must use this
//   one field: mixing two fields biases a chain without any visible error. The chart tangents are not
//   generators for that reason: on a sphere or disk dp/du turns within the tangent plane as the point
//   moves, a rotation B would not contain. Where a walk crosses from one region into another (or one
//   triangle into another with a different dominant axis) the coordinates jump: the walk may fail, or
//   converge to the point whose coordinates in its own region are the target, which is what the
//   densities at that state (its own frame, its own J) describe.
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
    Vec3 frameU{1, 0, 0}, frameV{0, 1, 0}; // the frame generators a, b of the convention above
    int shape = -1;  // Scene::shapes index (-1: no surface)
    // A light vertex at infinity (environment, directional light): n is the unit direction toward it
    // from the scene and p a point far along it, and that direction stays the same whatever the other
    // vertices do. A chain holds such an end fixed: the positional constraint becomes a directional one
    // (HSLT Sec. 4.5, after Jakob 2013, p. 70), and the distance to it is infinite (no derivative).
    bool atInfinity = false;
    uint32_t prim = 0;
    Vec2 coords; // as SurfaceInteraction::coords
    double magnitude = 0;

    // Interior (specular or offset) vertices only.
    Scatter scatter = Scatter::Reflection;
    double eta = 1; // eta_o / eta_i of the generalized half vector (1 for reflection)
    Vec2 offset;    // constraint value held by walks: 0 if specular, the microfacet normal's o_i (ME Eq. 11)

    [[nodiscard]] bool onSurface() const { return lengthSquared(ng) > 0; }
    // The direction from `from` toward this vertex, not normalized (the fixed direction at infinity).
    [[nodiscard]] Vec3 seenFrom(const Vec3& from) const { return atInfinity ? n : p - from; }
    [[nodiscard]] RayEndpoint endpoint() const { return {p, ng, magnitude}; }
    // The tangent frame T(x) = [s t] of the convention above.
    [[nodiscard]] Vec3 s() const { return frameU - n * dot(frameU, n); }
    [[nodiscard]] Vec3 t() const { return frameV - n * dot(frameV, n); }
    // A world direction in frame coordinates: T^T w.
    [[nodiscard]] Vec2 frameCoordinates(const Vec3& w) const { return {dot(s(), w), dot(t(), w)}; }
    // Index-matched transmission: the half vector vanishes at the solution and is used unnormalized
    // (normalizing it would divide by zero).
    [[nodiscard]] bool indexMatched() const { return scatter == Scatter::Transmission && eta == 1; }
};

// A surface point (as Shape::surfaceAt gives it) with its chart orthonormalized (the convention
// above). Nothing when dp/du and dp/dv are degenerate (parallel or zero), or at a bump-mapped point
// (scene/bump_frame.h: its normal derivatives are not the bumped normal's).
[[nodiscard]] std::optional<ManifoldVertex> manifoldVertex(const SurfaceInteraction& si);
// A point without surface (pinhole, point light): position only, with the chart of the plane
// perpendicular to `axis` so that chart coordinates exist; n = axis, ng = 0, no curvature.
[[nodiscard]] ManifoldVertex pointVertex(const Vec3& p, const Vec3& axis);
// A light vertex at infinity seen along the unit direction `toward` (from the scene toward it), placed at
// the point `far` along it.
[[nodiscard]] ManifoldVertex infiniteVertex(const Vec3& far, const Vec3& toward);
// A point of a plane with unit normal `normal` (flat chart, no curvature): the virtual plane of the
// walk's last vertex.
[[nodiscard]] ManifoldVertex planeVertex(const Vec3& p, const Vec3& normal);

// The unit microfacet normal m on n's side whose frame coordinates T^T m equal `offset` (T is not
// orthonormal in general: solve the 2x2 Gram system); nothing when no unit vector has them.
[[nodiscard]] std::optional<Vec3> microfacetNormal(const ManifoldVertex& v, const Vec2& offset);

} // namespace lt
