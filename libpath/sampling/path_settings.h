// How the pixel estimators and the primary-sample-space chains sample paths: the path-length bound,
// where Russian roulette starts and how it decides, and BDPT's MIS heuristic. One record for BDPT, the
// path tracer, PSSMLT and MMLT, so that methods compared on a scene sample the same paths.
#pragma once

#include "math/spectrum.h"
#include "sampling/mis.h"
#include "util/error.h"

namespace lt {

struct PathSettings {
    int maxDepth = -1; // Mitsuba's meaning: the most edges a path may have (-1: unbounded)
    // The fewest edges a path may have: shorter ones are another estimator's. The Markov chains leave paths of
    // one and two edges to the direct part of the image (mcmc/direct_split.h), which sets 3 here.
    int minDepth = 1;
    int rrDepth = 5;   // from this many edges on, subpaths continue by Russian roulette
    MisHeuristic mis = MisHeuristic::Power;
    // BDPT, for tests: evaluate only this one strategy, unweighted (each strategy alone is unbiased for the
    // paths it can sample). -1 = all strategies with MIS.
    int onlyS = -1, onlyT = -1;

    // Throws lt::Error for a bound that is neither -1 nor positive: every estimator checks its settings so.
    void check() const {
        if (maxDepth == 0 || maxDepth < -1) throw Error("maxDepth must be -1 (unbounded) or at least 1");
        if (minDepth < 1 || (maxDepth > 0 && minDepth > maxDepth))
            throw Error("minDepth must be at least 1 and at most maxDepth");
    }
};

// Russian roulette survival probability from the throughput relative to the path's start (Mitsuba 0.5,
// pbrt-v4): q = min(0.95, max component of beta times etaScale). etaScale, the product of eta^2 over the
// refractions so far, undoes the radiance compression of entering a denser medium, so paths inside glass
// are not killed for it.
[[nodiscard]] inline double russianRouletteSurvival(const Spectrum& relativeBeta, double etaScale) {
    const double q = relativeBeta.maxValue() * etaScale;
    return q < 0.95 ? q : 0.95; // NaN compares false: a NaN throughput survives and is counted later
}

} // namespace lt
