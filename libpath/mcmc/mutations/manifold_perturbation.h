// The manifold perturbation of Manifold Exploration (Jakob & Marschner 2012, Sec. 5.1-5.2), for paths
// through specular and glossy chains: at a non-specular vertex x_a turn the direction toward x_{a+-1}
// by a von Mises-Fisher lobe, follow the chain after it (specular vertices with their lobe kinds kept,
// glossy ones treated as specular with their microfacet normals held) to the next non-specular vertex
// x_b', and carry the chain between x_b' and the next non-specular vertex x_c (held) along its manifold
// with the manifold walk (manifold/manifold_walk.h). It generalizes the lens, caustic and multi-chain
// perturbations: x_a the camera and x_b x_c joined by a chain is a caustic seen through glass, which
// none of them can move.
//
// Stages. With probability 1/4 x_a is the camera and the step goes toward the light (Mitsuba's preference
// for sensor-side perturbations); otherwise x_a is a uniformly chosen non-specular vertex and the step
// direction a fair coin, chosen again until the path has an x_b and x_c beyond the delta vertices. That
// choice depends only on which vertices are delta, which the perturbation keeps: its probability is the
// same at both states and cancels. The classification of the glossy vertices after it does not cancel
// (below).
//
// Kernel. The lobe around the current direction w_o has its peak at lambda^2 p(w_i -> w_o), p the
// density with which x_a samples w_o (its BSDF, the light's emission or the camera's ray), at least
// 1 / (4 pi) (Mitsuba's floor), taken at each state: T(y -> x) uses the concentration of y.
//
// Endpoint. When x_a is the light vertex on an area emitter and the step goes toward the eye, half of the
// time its position moves instead (ME Sec. 5.1): a 2-D Gaussian offset d in the tangent plane of x_a
// (standard deviation positionSigma), projected back onto the emitter along -n(x_a) (the first surface
// below, which must be the emitter's shape), and the chain up to x_c (held) walked to it; b = a. The
// surface density of the new point is N(d) |n(x_a) . n(x_a')|, and the reverse kernel must reach x_a
// from x_a' the same way (checked by casting that ray).
//
// Glossy chains (offset manifolds, ME Sec. 5.2 and App. A1). Walking from x_a toward x_b, each
// non-delta vertex passed is treated as specular with probability psi (specularProbability: 1 for delta
// vertices, 0 for diffuse ones and the endpoints, from the roughness in between); the first one that is
// not becomes x_b, and after it x_c the same way. A glossy vertex treated as specular keeps its offset o
// (its constraint value, the microfacet normal in its frame) through the propagation of the turned chain
// and the walk, so the perturbation moves on the manifold of fixed o with coordinates (x_b, o). When the
// classification puts x_b on the path's end the proposal is rejected (counted as a configuration change):
// drawing the classification again would make its probability depend on the roughness of the vertices
// passed, which the perturbation changes.
//
// T in the measure of f (markov_path.h strips the specular deltas, light to eye). The density f of
// Jakob & Marschner is one in area on the non-delta vertices; in the chart (x_b, o) it is f J with
// J = |d(x_b, x_held) / d(x_b, o)| (offsetChartDeterminant). Their move samples x_b' with the area density
// T1 = D_perp(w_o') G(x_a <-> .. <-> x_b') (the chain's vertices holding their constraint values) under the
// classification of probability Psi = prod psi or (1 - psi) (x_b and x_c: 1 - psi), so the acceptance is
// f(y) J(y) Psi(y) T1(y -> x) / (f(x) J(x) Psi(x) T1(x -> y)): J multiplies f, as Mitsuba places it (ME
// Eq. 12 prints it inside T). lt's f~ differs from their f by prod G(edges) / G(run) per run of delta
// vertices, G(run) the generalized geometry term (ME Eq. 9) from the light end (deltaRunFactor).
// Multiplying T by the same factor of y keeps f / T, so
//   T~(x -> y) = Psi(x) / J(y) x [D(w_o') |cos| / d^2 at x_{a+-1}' x |det d x_{a+-1}' / d x_b'|]
//                x prod over the delta runs between x_a and x_c of y of G(edges) / G(run),
// the determinant from the turned chain's tangent maps with x_a held.
//
// Known limit: walks through held glossy vertices on veach-bidir's curved lamp shade (a triangle mesh)
// come back less often than delta chains (8 % of walks not reversible against 2 %): those proposals are
// rejected, not biased; the cause is not settled (a frame field independent of the triangles' uv charts
// did not change it). Not built yet: ME's move of the camera vertex across a thin lens's aperture (the
// perturbation keeps the lens point; the bidirectional mutation and the lens perturbation move it).
#pragma once

#include <atomic>
#include <span>

#include "manifold/manifold_walk.h"
#include "math/von_mises_fisher.h"
#include "mcmc/mutation.h"
#include "mcmc/mutation_registry.h"
#include "mcmc/mutations/walk_figures.h"
#include "mcmc/mutations/specular_chain.h"

namespace lt {

class ManifoldPerturbation final : public Mutation {
public:
    // Its row of the registry (mcmc/mutation_registry.h).
    static const MutationKind Kind;

    // lambda: the lobe's peak relative to the BSDF's sampling density (ME Sec. 5.1: 50 .. 500).
    // normalChange: Delta-theta of ME App. A1, the mean angle by which a perturbation turns the microfacet
    // normal at x_b (radians; measured in a pre-run by measureNormalChange, then held fixed so that the
    // chain stays Markov; Mitsuba starts from 1 degree).
    explicit ManifoldPerturbation(const Scene& scene, double lambda = 50, double normalChange = Pi / 180);

    [[nodiscard]] std::string name() const override { return Kind.name; }
    [[nodiscard]] bool suitable(const MarkovPath& x) const override;
    void propose(const MarkovPath& x, Pcg32& rng, Proposal& out) const override;
    // Its walks (mcmc/mutations/walk_figures.h).
    [[nodiscard]] std::unique_ptr<MutationFigures> makeFigures() const override {
        return std::make_unique<WalkFigures>();
    }

    // The vertices a perturbation works on: the turned vertex a, the moved vertex b, the held vertex c
    // (indices light to eye; b between a and c).
    struct Stages {
        int a = 0, b = 0, c = 0;
        bool endpoint = false; // x_a (the light vertex) moves on its emitter; then b = a
        [[nodiscard]] int step() const { return c > a ? 1 : -1; }
    };
    // The stages of a proposal from a suitable x, drawn as the header comment says (the first numbers
    // propose() draws); nothing when the classification left x_b on the path's end.
    [[nodiscard]] std::optional<Stages> chooseStages(const MarkovPath& x, Pcg32& rng) const;
    // The stages starting at a in direction step with only the delta vertices specular, or nothing when
    // the path ends before c.
    [[nodiscard]] static std::optional<Stages> stagesFrom(const MarkovPath& path, int a, int step);
    // psi(v): the probability that v is treated as specular (ME App. A1 in its printed form, psi = 1 - R
    // with R = (1 - cos theta_q) / (1 - cos(theta_q + Delta-theta)), theta_q = atan(-alpha^2 log(1 - 0.9))).
    [[nodiscard]] double specularProbability(const PathVertex& v) const;
    // Psi: the probability of the classification the stages s stand for, at the state `path`.
    [[nodiscard]] double stagesProbability(const MarkovPath& path, const Stages& s) const;
    // J = |d(x_b, x_held) / d(x_b, o)| of the header comment at `path` (1 without held glossy vertices).
    [[nodiscard]] double offsetFactor(const MarkovPath& path, const Stages& s) const;

    // The direction kernel of a state at x_a.
    [[nodiscard]] VonMisesFisher kernel(const MarkovPath& path, const Stages& s) const;
    // The endpoint kernel's standard deviation at the light vertex of `path`: 1 / sqrt(2 pi p lambda^2), p
    // the emitter's area density of its position, so that the Gaussian's peak is lambda^2 p (ME Sec. 5.1).
    [[nodiscard]] double positionSigma(const MarkovPath& path) const;
    // T~(from -> to) (header comment), from the two states alone; 0 when a Jacobian is singular.
    [[nodiscard]] double transitionDensity(const MarkovPath& from, const MarkovPath& to, const Stages& s) const;

    // prod G(edges) / G(run) of the delta run between the non-delta vertices `held` and `moving` (G(run)
    // the light-to-eye generalized geometry term, taken with `held` fixed and turned into the light-to-eye
    // one when `held` is the eye end); 1 without delta vertices between them, 0 where a Jacobian is
    // singular. `moving` must lie on a surface.
    [[nodiscard]] double deltaRunFactor(const MarkovPath& path, int held, int moving) const;

private:
    // The product of deltaRunFactor over the delta runs between the non-delta vertices from and to.
    [[nodiscard]] double deltaRunsFactor(const MarkovPath& path, int from, int to) const;
    // The stripped density of x_{a+-1} .. x_b given the direction density at x_a (the bracket and the
    // turned chain's runs of the header comment).
    [[nodiscard]] double turnedChainDensity(const MarkovPath& path, const Stages& s, double pdfDir) const;
    // The endpoint move's new light vertex for the tangent offset d at `from`'s light vertex, or nothing when
    // the projection along -n misses the emitter; `density` is set to its surface density N(d) |cos|.
    [[nodiscard]] std::optional<PathVertex> movedLight(const MarkovPath& from, const Vec3& d, double& density) const;
    // The turned chain through held glossy vertices: from `ray` (leaving x_a) to x_b', each vertex
    // scattering about its held microfacet normal (manifold/manifold_walk.h scatterHeld) on the same shape.
    [[nodiscard]] std::optional<RejectCause> followHeldChain(const MarkovPath& x, MarkovPath& y, const Stages& s,
                                                             Ray ray) const;

    const Scene& scene_;
    SensorWindow sensor_;
    double lambda2_;
    double normalChange_;
    WalkSettings walk_;
};

// The pre-run of ME App. A1: the mean angle by which the manifold perturbation (lambda, Delta-theta of
// 1 degree) turns the microfacet normal at x_b, over `proposals` proposals from the suitable `states` in
// turn (those that reach a path); 1 degree when none does. Stops early when *stop becomes true.
struct NormalChange {
    double radians = Pi / 180;
    size_t proposed = 0; // proposals made
    size_t measured = 0; // of them, those that reached a path
};
[[nodiscard]] NormalChange measureNormalChange(const Scene& scene, double lambda, std::span<const MarkovPath> states,
                                               size_t proposals, uint64_t seed,
                                               const std::atomic<bool>* stop = nullptr);

} // namespace lt
