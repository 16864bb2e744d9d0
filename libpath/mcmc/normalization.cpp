#include "mcmc/normalization.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "util/error.h"

namespace lt {

void NormalizationEstimate::take(NormalizationEstimate& other) {
    if (other.strata_.size() > strata_.size()) strata_.resize(other.strata_.size());
    for (size_t k = 0; k < other.strata_.size(); ++k) {
        Stratum& s = strata_[k];
        Stratum& o = other.strata_[k];
        s.count += o.count;
        s.known += o.known;
        s.sum += o.sum;
        s.knownSum += o.knownSum;
        s.sumOfSquares += o.sumOfSquares;
        o = Stratum{};
    }
}

double NormalizationEstimate::b() const {
    double b = 0;
    for (size_t k = 0; k < strata_.size(); ++k)
        b += stratumB(k);
    return b;
}

uint64_t NormalizationEstimate::samples() const {
    uint64_t n = 0;
    for (const auto& s : strata_)
        n += s.count;
    return n;
}

double NormalizationEstimate::stratumVariance(size_t k) const {
    const Stratum& s = strata_[k];
    if (s.count == 0) return 0;
    if (s.known < 2) return std::numeric_limits<double>::quiet_NaN();
    // The spread of the known values, for all the stratum's samples.
    const double knownMean = s.knownSum / double(s.known);
    return std::max(0.0, (s.sumOfSquares - double(s.known) * knownMean * knownMean) / double(s.known - 1));
}

double NormalizationEstimate::stratumDeviation(size_t k) const { return std::sqrt(stratumVariance(k)); }

double NormalizationEstimate::stratumStandardError(size_t k) const {
    const uint64_t count = strata_[k].count;
    return count ? std::sqrt(stratumVariance(k) / double(count)) : 0.0;
}

double NormalizationEstimate::relativeStandardError() const {
    double variance = 0;
    for (size_t k = 0; k < strata_.size(); ++k) {
        const double se = stratumStandardError(k);
        variance += se * se;
    }
    const double b = this->b();
    return b > 0 ? std::sqrt(variance) / b : std::numeric_limits<double>::quiet_NaN();
}

std::vector<uint64_t> neymanAllocation(const std::vector<double>& deviation, const std::vector<double>& cost,
                                       const std::vector<uint64_t>& have, double work) {
    const size_t n = deviation.size();
    std::vector<uint64_t> add(n, 0);
    std::vector<double> sigma(n, 0.0);
    double total = work, norm = 0;
    for (size_t k = 0; k < n; ++k) {
        if (!(cost[k] > 0)) throw Error("Neyman allocation: the cost of a sample must be positive");
        sigma[k] = std::isfinite(deviation[k]) ? deviation[k] : 0.0;
        total += double(have[k]) * cost[k];
        norm += sigma[k] * std::sqrt(cost[k]);
    }
    if (!(norm > 0) || !(work > 0)) return add;
    // The allocation for the total work: n_k = total (sigma_k / sqrt(c_k)) / sum_j sigma_j sqrt(c_j), so that
    // sum_k n_k c_k = total. Strata above their share keep what they have, so the others' shortfall can
    // exceed `work`: then it is scaled down to fit.
    std::vector<double> want(n, 0.0);
    double wantWork = 0;
    for (size_t k = 0; k < n; ++k) {
        want[k] = std::max(0.0, total * sigma[k] / std::sqrt(cost[k]) / norm - double(have[k]));
        wantWork += want[k] * cost[k];
    }
    const double scale = wantWork > work ? work / wantWork : 1.0;
    for (size_t k = 0; k < n; ++k)
        add[k] = uint64_t(want[k] * scale);
    return add;
}

} // namespace lt
