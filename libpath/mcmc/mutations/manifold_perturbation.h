// The manifold perturbation of Manifold Exploration (Jakob & Marschner 2012, Sec. 5.1), for paths
// through ideal specular chains: at a non-specular vertex x_a turn the direction toward x_{a+-1} by a
// von Mises-Fisher lobe, follow the specular vertices after it with their lobe kinds kept to the next
// non-specular vertex x_b', and carry the specular chain between x_b' and the next non-specular vertex
// x_c (held) along its manifold with the manifold walk (manifold/manifold_walk.h). It generalizes the
// lens, caustic and multi-chain perturbations: x_a the camera and x_b x_c joined by a chain is a caustic
// seen through glass, which none of them can move.
//
// Stages. With probability 1/4 x_a is the camera and the step goes toward the light (Mitsuba's preference
// for sensor-side perturbations); otherwise x_a is a uniformly chosen non-specular vertex and the step
// direction a fair coin, chosen again until x_b and x_c lie on the path. The choice depends only on
// which vertices are specular, which the perturbation keeps: its probability is the same at both states
// and cancels.
//
// Kernel. The lobe around the current direction w_o has its peak at lambda^2 p(w_i -> w_o), p the
// density with which x_a samples w_o (its BSDF, the light's emission or the camera's ray), at least
// 1 / (4 pi) (Mitsuba's floor), taken at each state: T(y -> x) uses the concentration of y.
//
// T in the measure of f (markov_path.h strips the specular deltas, light to eye). Jakob & Marschner's
// T(x -> y) = D_perp(w_o') G(x_a <-> .. <-> x_b') is the area density of x_b' with every other vertex
// determined; f(y) / T(x -> y) is what enters the acceptance. lt's f~ differs from their f by a factor
// per specular chain, prod G(edges) / G(chain), where G(chain) is the generalized geometry term
// (ME Eq. 9) with the light end held. Multiplying T by the same factor of y keeps f / T, so:
//   T~(x -> y) = [D(w_o') |cos| / d^2 at x_{a+-1}' x prod G of the turned chain's later edges]
//              x [prod G of the walked chain's edges except the one at x_c] / |det d x_{c-+1}' / d x_b'|,
// the last determinant from the walked chain's tangent maps with x_c held. Where x_c lies on the eye
// side (the camera, often: it has no area to move), that G is the eye-to-light term; the factor times
// prod R_imp / R_rad over the chain turns it into the light-to-eye one (walkedChainFactor).
//
// Not built yet: the endpoint position perturbation (light and aperture points move only through the
// bidirectional mutation) and glossy chains (offset manifolds, ME Sec. 5.2).
#pragma once

#include "manifold/manifold_walk.h"
#include "math/von_mises_fisher.h"
#include "mcmc/mutation.h"
#include "mcmc/mutations/specular_chain.h"

namespace lt {

class ManifoldPerturbation final : public Mutation {
public:
    // lambda: the lobe's peak relative to the BSDF's sampling density (ME Sec. 5.1: 50 .. 500).
    explicit ManifoldPerturbation(const Scene& scene, double lambda = 50);

    [[nodiscard]] std::string name() const override { return "manifold"; }
    [[nodiscard]] bool suitable(const MarkovPath& x) const override;
    void propose(const MarkovPath& x, Pcg32& rng, Proposal& out) const override;

    // The vertices a perturbation works on: the turned vertex a, the moved vertex b, the held vertex c
    // (indices light to eye; b between a and c).
    struct Stages {
        int a = 0, b = 0, c = 0;
        [[nodiscard]] int step() const { return b > a ? 1 : -1; }
    };
    // The stages of a proposal from x, drawn as the header comment says (the first numbers propose()
    // draws); nothing when x is not suitable.
    [[nodiscard]] static std::optional<Stages> chooseStages(const MarkovPath& x, Pcg32& rng);
    // The stages starting at a in direction step, or nothing when the path ends before c.
    [[nodiscard]] static std::optional<Stages> stagesFrom(const MarkovPath& path, int a, int step);

    // The direction kernel of a state at x_a.
    [[nodiscard]] VonMisesFisher kernel(const MarkovPath& path, const Stages& s) const;
    // T~(from -> to) (header comment), from the two states alone; 0 when a Jacobian is singular.
    [[nodiscard]] double transitionDensity(const MarkovPath& from, const MarkovPath& to, const Stages& s) const;

    // prod G(edges) / G(chain) of the chain between b and c, G(chain) the light-to-eye generalized geometry
    // term (1 without specular vertices; 0 where the chain's Jacobian is singular).
    [[nodiscard]] double walkedChainFactor(const MarkovPath& path, const Stages& s) const;

private:
    // The stripped density of x_{a+-1} .. x_b given the direction density at x_a.
    [[nodiscard]] double turnedChainDensity(const MarkovPath& path, const Stages& s, double pdfDir) const;

    const Scene& scene_;
    SensorWindow sensor_;
    double lambda2_;
    WalkSettings walk_;
};

} // namespace lt
