// Veach and Guibas' bidirectional mutation (Veach 1997, Sec. 11.4): delete a range of vertices x_{l+1} ..
// x_{m-1} and replace it by ka - 1 new vertices, s sampled from the light side (from x_l) and the rest
// from the eye side (from x_m), joined by a deterministic connection. It changes path length and
// configuration and regenerates whole paths, so it makes the chain ergodic; every other mutation is
// mixed with it.
//
// Proposal (lt's choice; Mitsuba uses two-tailed geometric laws of the same shape):
// * kd edges deleted, P(kd) proportional to 2^-|kd - 2| on the admissible kd;
// * the range start l uniform over its admissible values; l = -1 deletes the light vertex too (it is
//   then re-sampled on an area emitter or as a direction of the environment, from the light side or by
//   an eye subpath that hits the emitter or escapes to the sky; a point light's position and a
//   directional light's direction are never re-sampled); m = k + 1 deletes the camera vertex of a thin
//   lens too (Veach 1997 Sec. 11.4: the lens point is a vertex like any other; it is re-sampled uniform
//   on the aperture by the eye side, which then starts there; a pinhole never moves);
// * ka edges added, P(ka) proportional to 2^-|ka - kd|, |ka - kd| <= 8, within the maximum length;
// * the split s uniform in [0, ka - 1].
// T(x -> y) sums over every split that could have produced y (the same y comes from any of them); the
// reverse move deletes the new range and re-adds kd edges.
#pragma once

#include "math/distribution.h"
#include "mcmc/mutation.h"
#include "mcmc/mutation_registry.h"

namespace lt {

class BidirectionalMutation final : public Mutation {
public:
    // Its row of the registry (mcmc/mutation_registry.h).
    static const MutationKind Kind;

    // maxEdges: the longest path the chain may reach (the scene's maxDepth, or a bound when unbounded); minEdges the
    // shortest (PathSettings::minDepth: the direct split leaves paths of one and two edges out of the chains).
    BidirectionalMutation(const Scene& scene, int maxEdges, int minEdges = 1);

    [[nodiscard]] std::string name() const override { return Kind.name; }
    [[nodiscard]] bool suitable(const MarkovPath&) const override { return true; }
    void propose(const MarkovPath& x, Pcg32& rng, Proposal& out) const override;

    // The probability of choosing (kd, l, ka) at a path of k edges; 0 when not admissible.
    [[nodiscard]] double rangeProbability(int k, bool lightMovable, int kd, int l, int ka) const;
    // Whether the camera vertex may be re-sampled (a thin lens).
    [[nodiscard]] bool cameraMovable() const { return cameraMovable_; }
    // Sum over the splits s' of the delta-stripped density of sampling the vertices lo .. hi of `path`
    // (the new ones) that way, each split with probability 1 / (hi - lo + 2). `splitDensity` receives the
    // density of split `split`.
    [[nodiscard]] double newVertexDensity(const MarkovPath& path, int lo, int hi, int split = -1,
                                          double* splitDensity = nullptr) const;
    // Whether the light vertex of a path may be re-sampled (on an area emitter, or the environment).
    [[nodiscard]] bool lightMovable(const MarkovPath& path) const;

private:
    // A proposal's choice: kd edges deleted from x_l to x_m = x_{l + kd}, ka added, s of the new vertices from
    // the light side and t from the eye side.
    struct Range {
        int kd = 1, l = 0, m = 0, ka = 0, s = 0, t = 0;
    };
    // The range, drawn (nothing when no length may be added).
    [[nodiscard]] std::optional<Range> chooseRange(int k, bool lightMovable, Pcg32& rng) const;
    // The s light-side vertices after `light` (the prefix x_0 .. x_l), their density multiplied into `sampled`.
    [[nodiscard]] std::optional<RejectCause> sampleLightSide(const Range& r, Pcg32& rng, std::vector<PathVertex>& light,
                                                             double& sampled) const;
    // The t eye-side vertices after `eye` (the suffix, eye to light); with `lightDeleted` the last may escape to
    // the sky.
    [[nodiscard]] std::optional<RejectCause> sampleEyeSide(const MarkovPath& x, const Range& r, bool lightDeleted,
                                                           Pcg32& rng, std::vector<PathVertex>& eye,
                                                           double& sampled) const;
    [[nodiscard]] double deletedProbability(int k, bool lightMovable, int kd) const;
    [[nodiscard]] double addedProbability(int k, int kd, int l, int ka) const;
    // The last admissible range start for kd deleted edges (m = l + kd = k + 1 re-samples the camera vertex).
    [[nodiscard]] int highestStart(int k, int kd) const { return k - kd + (cameraMovable_ && kd >= 2 ? 1 : 0); }

    const Scene& scene_;
    int maxEdges_, minEdges_;
    SensorWindow sensor_;
    bool cameraMovable_ = false;
    double movableEmitterMass_ = 0; // selection probability of the emitters whose vertex can move (area, environment)
    DiscreteDistribution movableSelection_; // the emitter selection restricted to those emitters
};

} // namespace lt
