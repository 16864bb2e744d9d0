// The manifold walk (ME section 4, `WalkManifold`): move one endpoint of a
// specular chain to a target and carry the interior vertices along the (offset) specular manifold by
// Newton predictor-corrector steps. Failures are results, never exceptions: in MCMC a failed walk is
// a rejected proposal.
#pragma once

#include <span>
#include <variant>
#include <string_view>

#include "manifold/manifold_chain.h"
#include "scene/scene.h"

namespace lt {

enum class WalkFailure : uint8_t {
    None,                    // converged
    Diverged,                // iteration cap reached without getting within the tolerance
    Occluded,                // a segment is blocked by another object (the final x_{n-1} <-> x_n' included)
    TotalInternalReflection, // a refraction of the chain has no transmitted direction
    LeftSurface,             // a ray missed the chain's shape, hit it from the other side, or missed the plane
    Singular,                // A not invertible: the target lies on a caustic fold (ME section 4)
    Collapsed,               // two consecutive vertices coincide (Mitsuba's extra check)
    NonReversible,           // the reverse walk did not return to the start (ME section 5.1 step 4)
    Count
};
inline constexpr size_t WalkFailureCount = size_t(WalkFailure::Count);
[[nodiscard]] std::string_view walkFailureName(WalkFailure f);

struct WalkSettings {
    int maxIterations = 20;          // N (ME section 4)
    double relativeTolerance = 1e-7; // epsilon, relative to the scene's bounding-box diagonal (not to
                                     // coordinates, which are tiny near the origin)
    bool checkVisibility = true;     // test x_{n-1} <-> x_n' on the real geometry after convergence
};

// Which endpoint of the chain moves; the other stays pinned. Moving the first endpoint walks the
// reversed chain, so light-end and eye-end walks are the same code.
enum class WalkEnd : uint8_t { Last, First };

struct WalkResult {
    WalkFailure failure = WalkFailure::None;
    int iterations = 0;  // predictor-corrector steps taken (accepted or not)
    ManifoldChain chain; // converged: the new chain, in the input's order, its moved end = the target
    [[nodiscard]] bool converged() const { return failure == WalkFailure::None; }
};

// Walk `chain` (>= 2 vertices, interior set up by setScattering) until its `moving` endpoint reaches
// `target` (a point on real geometry, e.g. manifoldVertex of a hit). The corrector traces from the
// pinned end toward the predicted second vertex, reflects or refracts about each vertex's held
// microfacet normal (its offset in the new local frame) on the same shape, and ends on the virtual
// plane through x_n and x_n' (ME's symmetric normal), ignoring the scene there. When the iteration cap
// is reached, the failure is the cause of the last rejected step (Diverged if it traced but did not
// get closer).
[[nodiscard]] WalkResult walkManifold(const Scene& scene, std::span<const ManifoldVertex> chain,
                                      const ManifoldVertex& target, WalkEnd moving = WalkEnd::Last,
                                      const WalkSettings& settings = {});

// The ray from chain vertex `from` toward the point `toward` (direction not normalized). From a light vertex at
// infinity it keeps the light's fixed direction and comes from beyond the scene through `toward` (the
// directional constraint, HSLT Sec. 4.5 after Jakob 2013 p. 70): what moves is where the beam meets x_1.
[[nodiscard]] Ray rayToward(const Scene& scene, const ManifoldVertex& from, const Vec3& toward);

// The first surface along from -> dir (dir unit), its hit refined in double precision from the exact
// origin: Embree intersects in float from an offset origin, while walks need ~1e-7 relative accuracy (ME
// section 4). The ray is intersected with the hit triangle's plane, or the analytic shape again. The
// one place walks and HSLT's projections trace.
[[nodiscard]] std::optional<SurfaceInteraction> traceSurface(const Scene& scene, const ManifoldVertex& from,
                                                             const Vec3& dir);

// The scattering of an interior chain vertex v (scatter, eta and offset set; its new position) for the
// direction wi (unit, away from v): reflected or refracted about the microfacet normal its held offset
// gives in v's frame (m = n for a specular vertex). The configuration must stay what it was: wi on the
// side of the geometric normal that the old vertex's incoming direction oldWi was on (oldNg its
// normal), and the outgoing direction on the reflected or transmitted side. The one place the walk's
// corrector and MEMLT's propagation through held vertices scatter.
[[nodiscard]] std::variant<Vec3, WalkFailure> scatterHeld(const ManifoldVertex& v, const Vec3& wi, const Vec3& oldWi,
                                                          const Vec3& oldNg);

struct PropagateResult {
    WalkFailure failure = WalkFailure::None;
    ManifoldChain chain; // on success: x_1, the traced interior vertices, and the hit on the plane
};

// The corrector of the walk (ME section 4 line 4, section 5.2 for offset vertices), also MEMLT's
// deterministic propagation (ME section 5.1 step 2): from the pinned chain[0] toward `toward` through
// the chain's scatterings about each vertex's held microfacet normal (its offset in the new local
// frame), requiring the same shape and side at every vertex; the last segment ends on the plane
// through plane.p with normal plane.n, ignoring the scene. A last segment shorter than `collapse` fails
// (Mitsuba's extra check: the last two vertices converged onto the same point).
[[nodiscard]] PropagateResult propagateChain(const Scene& scene, std::span<const ManifoldVertex> chain,
                                             const Vec3& toward, const ManifoldVertex& plane, double collapse);

// Every vertex of `a` within `tolerance` (a distance) of the same vertex of `b` (chains of one length):
// how the reverse checks of the walks decide that a walk came back.
[[nodiscard]] bool sameChain(std::span<const ManifoldVertex> a, std::span<const ManifoldVertex> b, double tolerance);

// The reversibility check of ME section 5.1 step 4: walk `walked` (the result of walking `original`)
// back to the original's moving endpoint and require every vertex to return within
// `relativeTolerance` of the scene diagonal. The result's failure is NonReversible when the walk
// converged elsewhere.
[[nodiscard]] WalkResult reverseWalk(const Scene& scene, std::span<const ManifoldVertex> original,
                                     std::span<const ManifoldVertex> walked, WalkEnd moving,
                                     const WalkSettings& settings = {}, double relativeTolerance = 1e-5);

} // namespace lt
