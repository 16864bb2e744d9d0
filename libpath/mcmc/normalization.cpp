#include "mcmc/normalization.h"

#include <algorithm>
#include <cmath>
#include <limits>

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

double NormalizationEstimate::stratumStandardError(size_t k) const {
    const Stratum& s = strata_[k];
    if (s.count == 0) return 0;
    if (s.known < 2) return std::numeric_limits<double>::quiet_NaN();
    // The spread of the known values, for all the stratum's samples.
    const double knownMean = s.knownSum / double(s.known);
    const double variance =
        std::max(0.0, (s.sumOfSquares - double(s.known) * knownMean * knownMean) / double(s.known - 1));
    return std::sqrt(variance / double(s.count));
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

} // namespace lt
