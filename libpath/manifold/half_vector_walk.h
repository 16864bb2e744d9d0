// HSLT's h_to_positions (Kaplanyan, Hanika & Dachsbacher 2014, Sec. 5.1-5.2 and 7): move every interior
// vertex of a chain so that its constraint values c_i = T(x_i)^T h_i (the projected half vectors h-perp,
// specular_constraint.h) reach given targets, both endpoints fixed. The second walk over the manifold
// machinery's constraint blocks: where walkManifold (ME Sec. 4) moves one endpoint and re-traces the chain
// from the other, this one predicts all vertices at once, Delta X = J^{-1} (H* - H(X)) with the same
// block-tridiagonal J (the vertices' chart coordinates, manifold_vertex.h), and projects each predicted
// point onto the scene by a ray from its already projected neighbour, in the projection order (from a
// light at infinity, along its fixed direction: manifold_walk.h rayToward). A
// projection must hit the vertex's own shape from the same side, and every vertex keeps its configuration
// (each neighbour on the side of the geometric normal it was on: reflection stays reflection). A step that
// does not reduce the largest constraint error is retried with half the step (beta halving, HSLT Sec. 5.2);
// the walk converges when every |c_i - c_i*| is within the tolerance. Failures are results: in MCMC a
// failed walk is a rejected proposal.
#pragma once

#include <span>
#include <vector>

#include "manifold/manifold_walk.h"

namespace lt {

// HSLT Sec. 5.1: project from the light (x_1 first, each ray from x_{i-1} toward the predicted x_i) or
// from the eye (x_{k-1} first, rays from x_{i+1}).
enum class ProjectionOrder : uint8_t { FromLight, FromEye };

struct HalfVectorWalkSettings {
    int maxIterations = 20;  // predictor-corrector steps, halved ones included (ME's N)
    double tolerance = 1e-7; // on the largest |c_i - c_i*|; c is about the sine of h's angle to n
};

// Walk `chain` (>= 3 vertices, interior set up by setScattering) until its interior constraint values
// equal `targets` (one per interior vertex, chain order). The result's chain has the input's endpoints.
[[nodiscard]] WalkResult walkHalfVectors(const Scene& scene, std::span<const ManifoldVertex> chain,
                                         std::span<const Vec2> targets, ProjectionOrder order,
                                         const HalfVectorWalkSettings& settings = {});

// The projection-direction heuristic of HSLT Sec. 5.1 (their Table 2): from the eye when x_1 moves less
// than x_{k-1} to first order, |dx_1 / dx_{k-1}| = |T_1| / |T_{k-1}| < 1 (T_i = dx_i / dx_k with x_0
// held, the tangent maps of the chain), otherwise from the light (also when the maps do not exist).
[[nodiscard]] ProjectionOrder projectionOrder(const ChainJacobian& J);

// HSLT Sec. 5.2's reverse check: the walk from `walked` to `targets` (the original state's constraint
// values as the reverse proposal would set them), in the order the heuristic picks at `walked`, must bring
// every vertex back within `relativeTolerance` of the scene diagonal to `original`; NonReversible when it
// converges elsewhere.
[[nodiscard]] WalkResult reverseHalfVectorWalk(const Scene& scene, std::span<const ManifoldVertex> original,
                                               std::span<const ManifoldVertex> walked, std::span<const Vec2> targets,
                                               const HalfVectorWalkSettings& settings, double relativeTolerance);

// HSLT Sec. 5.2's jump between subspaces (their Fig. 8), for chains whose interior vertices all have a
// density in area measure (no specular vertex: a jump would not keep h = 0 there) and whose endpoints are
// points (no light at infinity: the projections and their G factors are rays from points). The first prediction of
// the walk, x'_j = x_j + (J^{-1} (H* - H(X)))_j on x_j's tangent plane, is projected in `order`: a ray from
// the already projected neighbour y toward x'_j, and whatever surface it meets first is the new vertex x''_j
// (any shape, either side: the jump may leave the subspace; the caller evaluates the path). `projection`
// turns the density of the predicted points into the density of the hits, area measure to area measure,
// through the shared direction from y (HSLT Sec. 5.2): prod_j G(y, x''_j) / G(y, x'_j), G(y, x'_j) with the
// tangent plane's normal.
struct SubspaceJump {
    std::vector<SurfaceInteraction> interior; // the hits x''_1 .. x''_{k-1}, chain order
    double projection = 0;
};
[[nodiscard]] std::optional<SubspaceJump> jumpSubspace(const Scene& scene, std::span<const ManifoldVertex> chain,
                                                       const ChainJacobian& J, const BlockTridiagonalLU& lu,
                                                       std::span<const Vec2> targets, ProjectionOrder order);

// The jump's preimage: the targets H* from which jumpSubspace at `from` (its Jacobian J, order `order`)
// lands on `to`, a chain with the same endpoints, with the jump's `projection` factor. The predicted point
// of vertex j is where the ray from to's neighbour (projected before it) through to_j meets from_j's
// tangent plane, so H* = H(from) + J (X' - X): unique. Nothing when a ray runs parallel to or away from that
// plane. Gives the reverse jump's density, and the forward one recomputed.
struct JumpPreimage {
    std::vector<Vec2> targets;
    double projection = 0;
};
[[nodiscard]] std::optional<JumpPreimage> jumpPreimage(std::span<const ManifoldVertex> from, const ChainJacobian& J,
                                                       std::span<const ManifoldVertex> to, ProjectionOrder order);

} // namespace lt
