// The specular constraint of one chain vertex and its row of the constraint Jacobian (ME Eq. 6-7,
// section 3.3 and App. A2). Frame convention: manifold_vertex.h.
//
// c_i(x_{i-1}, x_i, x_{i+1}) = T(x_i)^T h,  h = sigma (w_i + eta w_o) / |w_i + eta w_o|,
// with w_i, w_o the unit directions toward x_{i-1} and x_{i+1}, eta = eta_o / eta_i (1 for
// reflection) and sigma = +-1 orienting h to the side of the shading normal. At an index-matched
// interface h = w_i + w_o unnormalized (it vanishes at the solution). Ideal specular vertices sit on
// c = 0; glossy vertices treated as specular on c = o (offset manifolds, ME Eq. 11); the same vector
// is HSLT's half-vector state h-perp (HSLT Eq. 11).
#pragma once

#include <optional>

#include "bsdf/bsdf.h"
#include "manifold/block_tridiagonal.h"
#include "manifold/manifold_vertex.h"

namespace lt {

// One block row of grad C: A = dc/dx_{i-1}, B = dc/dx_i, C = dc/dx_{i+1}, each 2x2 with rows (s, t)
// and columns the chart coordinates (u, v) of the vertex moved; and the constraint value itself.
struct ConstraintRow {
    Vec2 value;
    Mat2 A, B, C;
};

// c_i; nothing when a segment has zero length or the (normalized) half vector is undefined.
[[nodiscard]] std::optional<Vec2> constraintValue(const ManifoldVertex& prev, const ManifoldVertex& v,
                                                  const ManifoldVertex& next);
// c_i and its three blocks, including the frame-rotation terms of B (curvature); nothing as above.
[[nodiscard]] std::optional<ConstraintRow> constraintRow(const ManifoldVertex& prev, const ManifoldVertex& v,
                                                         const ManifoldVertex& next);

// Set up interior vertex v for the scattering toward prev and next: reflection or transmission by the
// geometric normal (as Mitsuba classifies), eta = eta_o / eta_i from the BSDF's indices on the sides
// of the shading normal (the interior lies below it, bsdf.h), and offset = the current constraint
// value, or exactly 0 when `specular` (storing the rounding error would make walks drift). A
// transmission without indices (thin dielectric) goes straight through: index-matched, eta = 1. False
// when the constraint is undefined.
[[nodiscard]] bool setScattering(ManifoldVertex& v, const ManifoldVertex& prev, const ManifoldVertex& next,
                                 std::optional<InterfaceEta> eta, bool specular);

} // namespace lt
