// Otsu, Hanika and Dachsbacher's portal-based path perturbation ("Portal-Based Path Perturbation for
// Metropolis Light Transport", Sec. 4): the edge of a path that crosses a portal (a window, a door ajar)
// closest to the sensor turns about its crossing point, so both of its vertices move at once and the edge
// keeps passing through the opening. Veach's perturbations pivot about a vertex, often far from the
// opening, and the walls around it block most of their moves.
//
// Proposal (Sec. 4.3). The pivot p is kept (the paper's portal kernel T_A = delta), a direction w* is drawn
// around the edge's w0 (eye side toward light side) from the truncated reciprocal law of Eq. 5 (theta in
// [r_min, r_max], 2^-8 and 2^-4 rad by default, azimuth uniform), and the two vertices are the first hits
// from p along -w* (eye side) and +w* (light side: a point of an area emitter or, when the ray leaves the
// scene, the environment's direction, if the edge ended on a light).
//
// Density (Sec. 4.4, the extended path of Eq. 8-11). In the measure of f (area, or solid angle for a
// vertex at infinity) the pair has T = T_A(p) p_sigma(w*) / |n_portal . w*| G(x_p*, x_{p+1}*) (Eq. 10):
// lines through the portal, dA_portal dsigma_perp, are the throughput measure G dA dA of the edge (and
// |n . w| dA dsigma for a direction vertex, as geometryTerm has it). p_sigma depends on the angle alone
// and T_A's deltas are the same both ways, so both cancel in the ratio; the portal cosines do not, and
// are kept (the paper's "R = f / G for symmetric kernels" drops them).
//
// The reverse move (Sec. 4.5) must choose the same edge and the same pivot: a proposal whose new eye-side
// edge crosses a portal, or whose moved edge meets another portal before p, has T(y -> x) = 0 and is
// rejected as not reversible before it is evaluated.
//
// A delta vertex on the edge or next to it leaves no nearby path (the paper's early rejection, Sec. 4.5);
// here such paths are not suitable, so the driver picks another strategy for them instead of wasting a
// step. Portals are openings: a portal lying on geometry (a wall's face marked as one) would put the pivot
// on a surface, where the rays from it start ambiguously.
#pragma once

#include <optional>

#include "mcmc/mutation.h"
#include "mcmc/mutation_registry.h"
#include "mcmc/mutations/specular_chain.h"

namespace lt {

// Where a path crosses a portal: the edge (v[light], v[light + 1]) closest to the sensor whose two vertices
// can move (the eye side not the pinhole; the light side not a point or directional light, which no ray
// from the portal can reach), and on it the crossing closest to its eye-side vertex.
struct PortalCrossing {
    size_t edge = 0;      // the edge (v[edge], v[edge + 1]): v[edge] its light-side vertex
    Vec3 p, n;            // the crossing point and the portal's geometric normal there
    double magnitude = 0; // the portal primitive's largest coordinate (the float error of p scales with it)
};
[[nodiscard]] std::optional<PortalCrossing> portalCrossing(const Scene& scene, const std::vector<PathVertex>& v);

class PortalPerturbation final : public Mutation {
public:
    // Its row of the registry (mcmc/mutation_registry.h).
    static const MutationKind Kind;

    // `angles`: the direction kernel's range in radians (Eq. 5's r_min, r_max).
    PortalPerturbation(const Scene& scene, const ReciprocalKernel& angles);

    [[nodiscard]] std::string name() const override { return Kind.name; }
    // Suitable where the path crosses a portal on an edge that can move (Sec. 4.5: otherwise T(y -> x)
    // would be 0 for every y) and no delta vertex is on that edge or next to it.
    [[nodiscard]] bool suitable(const MarkovPath& x) const override;
    void propose(const MarkovPath& x, Pcg32& rng, Proposal& out) const override;

    // T of the moved pair of `to` (edge `edge`), proposed from a path that crossed the portal with normal n
    // along the direction `from` (unit, eye side toward light side): p_sigma(theta) / |n . w| G (T_A's delta
    // left out).
    [[nodiscard]] double density(const Vec3& from, const Vec3& n, const MarkovPath& to, size_t edge) const;

private:
    const Scene& scene_;
    ReciprocalKernel angles_;
};

} // namespace lt
