// The Metropolis-Hastings step shared by every chain (MCMC survey, Sec. 2.2), with expected-value
// ("Rao-Blackwellized") accumulation (SURVEY 2.6): each iteration credits the proposal with its
// acceptance probability a and the current state with 1 - a, whatever the random draw decides. The
// current state's credit is accumulated and splatted when the chain leaves it, or when the caller
// flushes (end of a round, a snapshot, the end of the run), so no credit is ever lost.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "image/film.h"
#include "mcmc/image_contribution.h"

namespace lt {

// The image estimator <I_j> = (b / N) sum_i h_j(x_i) f(x_i) / f*(x_i) (SURVEY Eq. 16): a state with
// credit w adds w f / f* at each of its contributions' raster positions. The film divides by the number
// of mutations (its "light paths") and multiplies by the pixel count, so `scale` = 1 / pixels; b, refined
// during the run, multiplies the film when it is read (mcmc/normalization.h).
// With strata (multiplexed MLT: path lengths, mcmc/normalization.h) each splat keeps its state's stratum and the image
// sums each stratum's credit, so that the runner can scale each stratum's splats apart (chain_run.h).
class ChainImage {
public:
    explicit ChainImage(double scale, size_t strata = 1) : scale_(scale), stratumCredit_(strata, 0.0) {}
    void add(const std::vector<ImageContribution>& c, double target, double credit, size_t stratum = 0) {
        if (!(credit > 0) || !(target > 0)) return;
        const double w = scale_ * credit / target;
        for (const auto& k : c) {
            splats_.push_back({k.raster, k.value * w});
            if (stratumCredit_.size() > 1) strata_.push_back(uint32_t(stratum));
        }
        stratumCredit_[stratum] += credit;
        luminanceCredit_ += credit * targetValue(c) / target;
    }
    std::vector<Splat>& splats() { return splats_; }
    // The stratum of each splat (empty without strata).
    [[nodiscard]] const std::vector<uint32_t>& strata() const { return strata_; }
    // The credit given to states of each stratum: the mutations spent there, in expectation over the acceptances.
    [[nodiscard]] const std::vector<double>& stratumCredit() const { return stratumCredit_; }
    // Sum of credit x targetValue(f) / f*: the credit itself for chains whose target is targetValue, and for
    // another target N times the chains' estimate of (integral of targetValue) / (integral of f*) (chain_run.h).
    [[nodiscard]] double luminanceCredit() const { return luminanceCredit_; }

private:
    double scale_;
    std::vector<Splat> splats_;
    std::vector<uint32_t> strata_;
    std::vector<double> stratumCredit_;
    double luminanceCredit_ = 0;
};

// The acceptance probability min(1, f*(y) T(y -> x) / (f*(x) T(x -> y))), written with the mutations'
// Q = T / f* (as in Mitsuba's libbidir): a = min(1, Q(y -> x) / Q(x -> y)). Zero when anything is not finite
// or the forward density vanishes: such a proposal is rejected, never accepted by accident.
[[nodiscard]] inline double acceptance(double forwardQ, double reverseQ) {
    if (!(forwardQ > 0) || !std::isfinite(forwardQ) || !(reverseQ >= 0) || !std::isfinite(reverseQ)) return 0;
    return std::min(1.0, reverseQ / forwardQ);
}

// A chain's current state as far as the image is concerned.
struct ChainPosition {
    std::vector<ImageContribution> contributions;
    double target = 0;
    double credit = 0;  // accumulated 1 - a of the proposals that did not leave it
    size_t stratum = 0; // ChainImage's strata

    // Credit a proposal (a in [0, 1]) of stratum `proposedStratum` and move to it when `move`.
    void step(std::vector<ImageContribution>& proposed, double proposedTarget, double a, bool move, ChainImage& image,
              size_t proposedStratum = 0) {
        image.add(proposed, proposedTarget, a, proposedStratum);
        credit += 1 - a;
        if (move) {
            image.add(contributions, target, credit, stratum);
            contributions.swap(proposed);
            target = proposedTarget;
            credit = 0;
            stratum = proposedStratum;
        }
    }
    void flush(ChainImage& image) {
        image.add(contributions, target, credit, stratum);
        credit = 0;
    }
};

} // namespace lt
