// The half-vector space mutation of HSLT (Kaplanyan, Hanika & Dachsbacher 2014, "The natural-constraint
// representation of the path space for efficient light transport simulation"): within the subspace of
// paths through the same surfaces in the same configuration, a path x_0 .. x_k is (x_0, h_1, .., h_{k-1},
// x_k), h_i the projected generalized half vector c_i = T(x_i)^T h_i of manifold/specular_constraint.h
// (HSLT Eq. 11). The mutation keeps both endpoints (the light point or direction, and the camera), draws a
// new h_i at every interior vertex that is not specular (specular ones keep h = 0 exactly, Sec. 4.4), finds
// the vertices with those half vectors (manifold/half_vector_walk.h: all vertices predicted at once by J^{-1}
// and projected by ray casting, the projection order by the heuristic of Sec. 5.1), checks that the walk
// back reaches the state (Sec. 5.2), and accepts with the densities of both states. Always mixed with
// the bidirectional mutation, which changes lengths and configurations (Sec. 5.1).
//
// Jumps between subspaces (Sec. 5.2, Fig. 8-9): where the walk fails to converge, the walk's first
// prediction, projected onto whatever surfaces its rays meet (half_vector_walk.h jumpSubspace), is
// proposed instead, with area-measure densities both ways: T(x -> y) = K_x(H*) |det J(x)| prod G(y_prev,
// y_j) / G(y_prev, x'_j). It is a move of its own in the Metropolis-Hastings sense (the move's kind is
// part of the proposal): x -> y is a jump only when x's regular walk toward the drawn H* fails, so the
// reverse jump's density counts only if y's regular walk toward the preimage of x fails as well (the
// paper's "bidirectionally invalid"), and each kind, with its own densities both ways, keeps detailed
// balance alone (a pair may be reachable by both kinds, through different half vectors). Only paths
// without specular vertices jump (a jump does not keep h = 0 at a specular vertex, so its f would vanish).
//
// Target in half-vector space (HSLT Eq. 4-5). With J = dH/dX the block-tridiagonal constraint Jacobian over
// the interior vertices (chart coordinates, orthonormal: area measure), f_H = f |det J|^{-1}. lt's f~ strips
// each specular vertex's Dirac delta in projected solid angle, light to eye (markov_path.h): at specular
// x_j the delta is delta(h_j) |dh_j / dw_o| / |cos_j| = delta(h_j) |det C_j| / G(x_j, x_{j+1}), C_j =
// dc_j / dx_{j+1} in x_{j+1}'s chart (the camera's chart faces the edge, matching G without a camera
// cosine). Integrating the deltas out (h_j = 0) leaves the density over the non-specular half vectors
//   f_H = f~ g,  g = prod_{j specular} |det C_j| / G(x_j, x_{j+1}) / |det J|,
// which is HSLT Eq. 5's "a specular vertex contributes just its kappa" in lt's measure (the closed form
// rho G(x_0, x_1) |T_1| prod(...) of Eq. 5 is checked against f~ / |det J| in the tests). The chain's
// target stays lum(f~) (every mutation of a mix shares it); HSLT's proposal enters through T~(x -> y) =
// T_H(x -> y) / g(y), the kernel density turned into lt's measure at y, so f~(y) T~(y -> x) / (f~(x)
// T~(x -> y)) = f_H(y) T_H(y -> x) / (f_H(x) T_H(x -> y)) (Sec. 5.1: the acceptance is exact).
//
// Kernel (HSLT Sec. 6-7), per non-specular interior vertex, from the state alone (the reverse kernel from
// the proposal's): an anisotropic Gaussian in the vertex's h-perp coordinates (math/gaussian2.h), centred
// at the current c_i. Standard deviations, per principal axis a:
//   sigma_a = min(sigma_bsdf, w_i v_a), sigma_bsdf = gamma alpha_i / sqrt 2 (and at least 1e-3 sigma_bsdf),
// alpha_i the Beckmann-equivalent roughness (Bsdf::roughness; 1 for diffuse BSDFs, and at most 1), alpha / sqrt 2 the
// Beckmann lobe's own standard deviation per axis (Sec. 6.1), gamma 0.1 (the paper's value for all its images); v_a and
// the axes the singular values and left singular vectors of [dh_u dh_v], dh = D_i^{-1} dx, dx_u and dx_v the raster's u
// and v pixel steps on x_{k-1}'s tangent plane (camera ray differentials, no tracing) scaled by `stratify` (2 %) of the
// image width and height, D_i = dx_{k-1} / dh_i the block of J^{-1} (Eq. 9); w_i = alpha_i / sum_j alpha_j (Sec. 6.3).
// The paper samples an anisotropic Phong lobe moved by a Moebius transform (Sec. 7) whose exponents come from
// supplementary material we do not have; the Gaussian is the variant of the HSLT follow-up code, in h-perp
// (the constraint the manifold machinery solves) rather than slope coordinates: its support is the whole
// plane, and proposals that no microfacet normal has (outside the disk the frame maps unit vectors to)
// fail the walk and are rejected. stratify 0 turns the image-plane limit off.
#pragma once

#include "manifold/half_vector_walk.h"
#include "math/gaussian2.h"
#include "mcmc/mutation.h"
#include "mcmc/mutation_registry.h"
#include "mcmc/mutations/walk_figures.h"

namespace lt {

class HalfVectorMutation final : public Mutation {
public:
    // Its row of the registry (mcmc/mutation_registry.h).
    static const MutationKind Kind;

    // gamma in (0, 1] (HSLT Sec. 6.1); stratify >= 0, the image-plane step as a fraction of the image.
    HalfVectorMutation(const Scene& scene, double gamma = 0.1, double stratify = 0.02, bool jumps = true);

    [[nodiscard]] std::string name() const override { return Kind.name; }
    // At least one non-specular interior vertex. A light vertex at infinity (environment, directional
    // light) is an endpoint held like the others: its direction stays, x_1 moves across its beam
    // (manifold_walk.h rayToward), and the densities need nothing else (f_H = f~ g above holds for any
    // fixed endpoints; the infinite end's distance gives no derivative, specular_constraint.cpp).
    [[nodiscard]] bool suitable(const MarkovPath& x) const override;
    void propose(const MarkovPath& x, Pcg32& rng, Proposal& out) const override;
    // Its walks (mcmc/mutations/walk_figures.h).
    [[nodiscard]] std::unique_ptr<MutationFigures> makeFigures() const override {
        return std::make_unique<WalkFigures>();
    }

    // A state in the manifold's charts: the whole path as one chain (its interior vertices set up for
    // their scattering, specular ones at offset 0), its Jacobian and factorization.
    struct State {
        ManifoldChain chain;
        ChainJacobian J;
        BlockTridiagonalLU lu;
    };
    [[nodiscard]] std::optional<State> state(const MarkovPath& path) const;
    // g = f_H / f~ (header comment); 0 where a determinant vanishes or is not finite.
    [[nodiscard]] double halfVectorFactor(const MarkovPath& path, const State& s) const;
    // The kernel of each interior vertex at a state (entries of specular vertices unused).
    [[nodiscard]] std::vector<Gaussian2> kernels(const MarkovPath& path, const State& s) const;
    // T~(from -> to) of the header comment; 0 when either state has no chart or factor.
    [[nodiscard]] double transitionDensity(const MarkovPath& from, const MarkovPath& to) const;
    // The walks' tolerance on |c - c*| for a state: from its materials alone (half_vector_mutation.cpp).
    [[nodiscard]] double walkTolerance(const MarkovPath& path) const;
    // A state the jump of HSLT Sec. 5.2 can leave and reach: no specular interior vertex, every one with a BSDF,
    // and no light vertex at infinity.
    [[nodiscard]] bool jumpable(const MarkovPath& x) const;
    // T(from -> to) of the jump (area measure, header comment), s and `to` the two states; 0 when `to` is
    // not a jump of `from`'s: no preimage, or `from`'s regular walk toward it converges.
    [[nodiscard]] double jumpDensity(const MarkovPath& from, const State& s, const State& to) const;

private:
    // T~ of transitionDensity from the states of both paths, the kernels at `from` and g(to).
    [[nodiscard]] static double kernelTransition(const MarkovPath& from, const State& a,
                                                 const std::vector<Gaussian2>& K, const State& b, double gTo);
    // After the regular walk toward `target` failed: the jump, proposed when valid (out.failed cleared).
    void proposeJump(const MarkovPath& x, const State& sx, const std::vector<Vec2>& target, double sampled,
                     ProjectionOrder order, Proposal& out) const;

    const Scene& scene_;
    double gamma_, stratify_;
    bool jumps_;
    HalfVectorWalkSettings walk_;
};

} // namespace lt
