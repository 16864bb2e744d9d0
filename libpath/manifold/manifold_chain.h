// A specular chain x_1 .. x_k (ME section 3.3): two non-specular endpoints and k - 2 specular (or
// offset) interior vertices; its constraint Jacobian, tangent maps and generalized geometry term.
#pragma once

#include <optional>
#include <span>
#include <vector>

#include "manifold/block_tridiagonal.h"
#include "manifold/manifold_vertex.h"

namespace lt {

using ManifoldChain = std::vector<ManifoldVertex>;

// The square part A of grad C over the interior vertices (rows and columns x_2 .. x_{k-1}), and the
// blocks coupling the endpoints: B_1 = dc_2/dx_1 and B_k = dc_{k-1}/dx_k (ME Fig. 3).
struct ChainJacobian {
    BlockTridiagonal A;
    Mat2 first, last;
    std::vector<Vec2> values; // the constraint values c_2 .. c_{k-1}
};

// Nothing when the chain has no interior vertex or a constraint is undefined (zero-length segment).
[[nodiscard]] std::optional<ChainJacobian> chainJacobian(std::span<const ManifoldVertex> chain);

// dx_i / dx_k for the interior vertices i = 2 .. k-1 with x_1 held (the right block column of
// ME's T_S = -A^{-1} [B_1 B_k]); nothing when A is singular (x_k on a caustic of x_1).
[[nodiscard]] std::optional<std::vector<Mat2>> tangentMaps(const ChainJacobian& J);

// ME Eq. 9: G(x_1 <-> ... <-> x_k) = |det(P_2 A^{-1} B_k)| G(x_1 <-> x_2), the derivative of
// projected solid angle at x_1 with respect to area at x_k with the chain held on its manifold; the
// ordinary geometry term (path/vertex.h) when k = 2. Uses the other form of Eq. 9 (B_1,
// G(x_{k-1} <-> x_k)) when x_k has no surface. Nothing when A is singular, both endpoints lack a
// surface, or a constraint is undefined.
[[nodiscard]] std::optional<double> generalizedGeometryTerm(std::span<const ManifoldVertex> chain);

// ME Sec. 5.2 (Fig. 11): |det d(x_m, x_held) / d(x_m, o_held)| for a chain x_1 .. x_k whose interior
// vertex m moves freely and whose other interior vertices keep their constraint values: 0 where
// specular[j], the offset o_j where not (glossy vertices treated as specular). A over the interior
// with m's rows replaced by [0 I 0] is d(x_m, c) / dx; its inverse without the specular vertices'
// rows and columns maps (x_m, o) to (x_m, x_held). m may be an endpoint (0 or k - 1: the moved vertex
// is the chain's end, fixed like the other end in this chart): then |det d x_held / d o_held|. 1 when
// no vertex holds an offset; nothing when A is singular or a constraint is undefined. `specular` has
// one entry per chain vertex (endpoints ignored).
[[nodiscard]] std::optional<double> offsetChartDeterminant(std::span<const ManifoldVertex> chain, size_t m,
                                                           const std::vector<bool>& specular);

// The geometry term between two chain vertices (path/vertex.h's geometryTerm: geometric normals,
// a point without surface contributes no cosine).
[[nodiscard]] double geometryTerm(const ManifoldVertex& a, const ManifoldVertex& b);

// The chain in the opposite order (walks from the other end), transmissions' eta inverted.
[[nodiscard]] ManifoldChain reversed(std::span<const ManifoldVertex> chain);

} // namespace lt
