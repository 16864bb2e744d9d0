// The normalization b = integral of f* over the image (Veach and Guibas 1997; Sik and Krivanek's MCMC
// survey, Sec. 2.5), estimated from independent samples and refined for as long as a run goes on.
//
// A Markov chain only knows f* up to scale, so the image estimator (b / N) sum f / f* takes b from
// independent samples. Fixing b once from the start-up leaves the run with a scale error that never
// shrinks: an error-against-time curve flattens at (relative error of b)^2, and on a scene whose light is
// carried by rare paths (a tiny lamp) a 10^5-sample start-up can miss most of b. So every chain keeps
// adding independent samples while it runs (large steps in primary sample space, BDPT samples in path
// space), and the film is scaled by the current estimate only when it is read: at each snapshot and at
// the end.
//
// Strata: b = sum_k b_k over strata k (multiplexed MLT: path lengths), each b_k the mean of its own
// independent samples X_k,i. Where the number of samples depends on values drawn before (the start-up's
// Neyman allocation, the large steps' length proposal), the mean is a ratio estimator, consistent with a
// bias of order 1 / n, far under its standard error. Var(b) = sum_k Var(X_k) / n_k, with Var(X_k)
// the samples' own spread; for a stratum that also holds a previous run's mean without its spread (a
// seed file's b), that mean counts as its samples and Var(X_k) comes from the samples whose values are
// known.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace lt {

class NormalizationEstimate {
public:
    explicit NormalizationEstimate(size_t strata = 1) : strata_(strata) {}

    // One independent sample of b_k: f*(x) / p(x) of a sample drawn with density p.
    void add(size_t stratum, double value) {
        Stratum& s = strata_[stratum];
        ++s.count;
        ++s.known;
        s.sum += value;
        s.knownSum += value;
        s.sumOfSquares += value * value;
    }
    // A previous estimate of b_k: the mean of `count` samples whose spread is not known (a seed file's b).
    void addMean(size_t stratum, double mean, uint64_t count) {
        strata_[stratum].count += count;
        strata_[stratum].sum += mean * double(count);
    }
    // Add another estimate's samples (the chains', in chain order after each round) and clear it.
    void take(NormalizationEstimate& other);

    [[nodiscard]] size_t strata() const { return strata_.size(); }
    // More strata, empty (multiplexed MLT's start-up adding path lengths); never fewer.
    void addStrata(size_t strata) { strata_.resize(std::max(strata, strata_.size())); }
    [[nodiscard]] double b() const;
    [[nodiscard]] double stratumB(size_t k) const {
        return strata_[k].count ? strata_[k].sum / double(strata_[k].count) : 0.0;
    }
    [[nodiscard]] uint64_t samples() const;
    [[nodiscard]] uint64_t stratumSamples(size_t k) const { return strata_[k].count; }
    // Standard error of b over b; NaN while some stratum with samples has fewer than two known values.
    [[nodiscard]] double relativeStandardError() const;
    // Standard error of b_k (NaN as above).
    [[nodiscard]] double stratumStandardError(size_t k) const;
    // Standard deviation of one sample of b_k (NaN as above; 0 without samples).
    [[nodiscard]] double stratumDeviation(size_t k) const;

private:
    // Variance of one sample of b_k (NaN while fewer than two values are known; 0 without samples).
    [[nodiscard]] double stratumVariance(size_t k) const;

    struct Stratum {
        uint64_t count = 0; // samples, including those of previous estimates
        uint64_t known = 0; // samples whose values (and so spread) are known
        double sum = 0, knownSum = 0, sumOfSquares = 0;
    };
    std::vector<Stratum> strata_;
};

// Neyman allocation with costs (Cochran, Sampling Techniques, 3rd ed., Sec. 5.5): for a given work
// sum_k n_k c_k, Var(b) = sum_k sigma_k^2 / n_k is least with n_k proportional to sigma_k / sqrt(c_k).
// Given the samples each stratum has (`have`), their deviations and costs per sample, returns the samples
// to add to each, at most `work` in all, that bring the counts toward that allocation for the total work
// (what `have` cost plus `work`): a stratum the allocation gives fewer than it has gets none. A deviation
// that is not finite counts as zero; all zero when every deviation is zero. Costs must be positive.
std::vector<uint64_t> neymanAllocation(const std::vector<double>& deviation, const std::vector<double>& cost,
                                       const std::vector<uint64_t>& have, double work);

} // namespace lt
