// Kelemen PSSMLT and multiplexed MLT over lt's BDPT (Kelemen et al. 2002; Hachisuka et al. 2014).
//
// Start-up (Veach-Guibas start-up bias removal, in primary sample space as Kelemen and pbrt-v3 do):
// independent primary samples give the first estimate of b = integral of f*, and every chain starts from one
// of them drawn in proportion to f* (systematic over the chain index). Their budget is `startupSamples`
// (multiplexed MLT: that many per path length on average, spread in inverse proportion to the length, the
// same work for each). A pilot spends 1/8 of it so; then rounds, each adding half the work done, a quarter of
// it spread so and the rest over the lengths by Neyman allocation (n_k proportional to sigma_k / sqrt(cost_k),
// mcmc/normalization.h), until b's relative standard error is at most `startupError`. Spread evenly, most of
// the work went to long paths that hold almost nothing: on cornell-box (65 lengths) Neyman allocation reaches
// the even spread's precision with 1/20 of the work. The even quarter keeps every length sampled, a rare
// light the pilot missed included (its samples show no spread, so Neyman allocation alone would give it
// nothing more, and b's standard error would not show what it misses). The counts of the later rounds depend
// on the values drawn before (so does the run's use of q below): the mean over all samples is consistent,
// its bias of order 1 / n, far under its standard error.
// b is then refined during the run: every large step is an independent uniform sample of f*, so its value joins the
// estimate whether it is accepted or not (mcmc/normalization.h), and the film is read with b as it then stands.
//
// Multiplexed MLT: the path length k is part of the state, so a chain can reach every length and no
// length is lost to a start-up that missed it. The target is f*(k, u) = f*_k(u), whose integral is
// b = sum_k b_k. A small step keeps k; a large step draws k' from a fixed distribution q and u' fresh, an
// independence proposal of density q(k') on (k', u'), accepted with
//   a = min(1, f*(k', u') q(k) / (f*(k, u) q(k'))).
// The best q for that acceptance is the target's own marginal b_k / b; q is the start-up's estimate of it
// mixed with a floor, q(k) = (1 - LengthFloor) b_k / b + LengthFloor (1 / k) / sum_j (1 / j), so that a
// length the start-up missed still gets a share of the large steps. The floor is spread in proportion to
// 1 / k, the inverse of a length's cost, so that every length gets the same work from it and a scene
// with 65 possible lengths does not spend most of its large steps on long, dark ones; at most LengthFloor
// of the large steps are "wasted" on lengths that carry no light. A large step at length k' is a sample
// of b_k' (u' is uniform), so each length's b_k is the mean of its own samples and b their sum.
//
// An unbounded depth: the chains cover lengths up to a bound L, so the paths beyond L are left out of the image and of
// b, a bias of their share of the light. Where the light needs many bounces (a kitchen lit through its windows,
// lengths 9 to 12 each held about a fifth of b) a fixed L = 12 lost 47 % of the image. So the start-up first covers
// `unboundedEdges` lengths, then estimates the b of all lengths beyond L by Russian roulette over the length (a
// length L + j, j drawn with probability (1 - c) c^(j - 1), f*(L + j, u) over that probability: unbiased for every c,
// which follows b's decay over the last two lengths), and while that tail holds more than TailBound of the total,
// doubles L (up to MaxUnboundedEdges, the cap on BDPT's subpaths), samples the new lengths and estimates the tail
// again. TailBound is a fifth of the start-up's default precision on b (--startup-error 0.005): what is left out
// stays well under b's own error. The tail estimate, L and whether the cap stopped the growth are in the output.
//
// Image scale per length: each length's splats are read with its own b_k over the chains' credit there
// (mcmc/chain_run.h), so a length the chains miss or under-visit does not move the others' scale.
//
// Proposals: a large step with probability `largeStepProbability`, otherwise Kelemen's exponential small
// step on every coordinate (mcmc/primary_sample_vector.h). Both are symmetric in u.
#pragma once

#include "mcmc/chain_run.h"
#include "mcmc/primary_sample_vector.h"

namespace lt {

enum class PrimarySpace { Kelemen, Multiplexed };

// Multiplexed MLT: the share of large steps spread evenly over the path lengths (file comment).
inline constexpr double LengthFloor = 0.1;
// Multiplexed MLT with an unbounded depth: the share of b the lengths beyond the chains' may hold, and the most
// edges the chains' lengths grow to (file comment).
inline constexpr double TailBound = 1e-3;
inline constexpr int MaxUnboundedEdges = 1023;

struct PrimarySpaceSettings {
    PrimarySpace space = PrimarySpace::Kelemen;
    PathSettings paths;
    int unboundedEdges = 12;           // multiplexed, paths.maxDepth -1: the lengths the start-up covers first
    double largeStepProbability = 0.3; // Mitsuba's default
    SmallStepKernel smallStep;
    uint64_t startupSamples = 100000; // the start-up's budget: Mitsuba's luminanceSamples; multiplexed: per
                                      // path length on average (lt-mutate's default there is 20000)
    double startupError = 0.005;      // the start-up ends once b's relative standard error is at most this
};

// Renders into `film` (its splats; the film's light-path count becomes the number of mutations).
// Throws lt::Error when the start-up finds no light at all.
ChainRunStats runPrimarySpaceChains(const Scene& scene, const PrimarySpaceSettings& space, const ChainRunSettings& run,
                                    SampleFilm& film, const RunControl& control);

} // namespace lt
