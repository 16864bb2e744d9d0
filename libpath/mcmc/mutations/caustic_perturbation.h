// Veach and Guibas' caustic perturbation (Veach thesis 11.4.3) for paths ending
// (D|L) S+ D E: turn the direction leaving x_l (the light end of the specular chain) by an angle theta
// with density proportional to 1 / theta on [theta1, theta2], follow the chain keeping each vertex's
// lobe kind to x_{k-1}', and connect it to the camera (the raster position follows).
//
// Ranges: theta_{1,2} = (radians per pixel) r_{1,2} d_E / d_L with the lens perturbation's raster radii,
// d_E = |x_{k-1} x_k| and d_L the length of the chain from x_l to x_{k-1}: x_{k-1} then moves on the
// image about as far as under the lens perturbation. They depend on the path, so the kernel is not
// symmetric and the reverse density needs the parameters of the proposal: T(y -> x) uses the ranges of
// y and is 0 when theta falls outside them.
//
// T in the measure of f: the solid-angle density of the new direction at x_l converted to the area of
// x_{l+1}', times G for each vertex after a specular one (the stripped density with the lobe fixed).
//
// A light at infinity (environment, directional light: sky or sun through glass) has no position to turn
// a direction at, and a directional light no other direction: there the direction stays and the parallel
// ray is moved sideways instead, by an offset of length r in the plane perpendicular to it with density
// proportional to 1 / r on [r1, r2], r_{1,2} = (radians per pixel) r_{1,2} d_E (a sideways move of the
// beam moves x_{k-1} about as far). Its density is one on that plane, which PathVertex::convertDensity
// turns into the area of x_1' (times |cos| there).
#pragma once

#include "mcmc/mutation.h"
#include "mcmc/mutation_registry.h"
#include "mcmc/mutations/specular_chain.h"

namespace lt {

class CausticPerturbation final : public Mutation {
public:
    // Its row of the registry (mcmc/mutation_registry.h).
    static const MutationKind Kind;

    explicit CausticPerturbation(const Scene& scene);

    [[nodiscard]] std::string name() const override { return Kind.name; }
    [[nodiscard]] bool suitable(const MarkovPath& x) const override;
    void propose(const MarkovPath& x, Pcg32& rng, Proposal& out) const override;

    // The range of the step of a suitable path: the angle theta, or at a light at infinity the sideways
    // offset r (evaluated at each state: T(y -> x) needs y's own range).
    [[nodiscard]] ReciprocalKernel steps(const MarkovPath& path) const;
    // The density of a step of that size, azimuth uniform, in x_l's measure (solid angle; at infinity the
    // plane perpendicular to the rays).
    [[nodiscard]] double stepDensity(const MarkovPath& path, double step) const;
    // The stripped area density of the chain's vertices x_{l+1} .. x_{k-1} given the step's density.
    [[nodiscard]] double chainDensity(const MarkovPath& path, double pdfStep) const;
    // x_l: the non-specular vertex or light at the light end of the chain before x_{k-1}.
    [[nodiscard]] static int chainStart(const MarkovPath& path);

private:
    const Scene& scene_;
    double radiansPerPixel_;
    ReciprocalKernel radius_;
};

} // namespace lt
