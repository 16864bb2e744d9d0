#include "math/distribution.h"

#include <algorithm>
#include <cmath>

#include "util/error.h"

namespace lt {

DiscreteDistribution::DiscreteDistribution(std::span<const double> weights) {
    cdf_.resize(weights.size() + 1);
    pmf_.resize(weights.size());
    cdf_[0] = 0;
    for (size_t i = 0; i < weights.size(); ++i) {
        if (!(weights[i] >= 0) || !std::isfinite(weights[i]))
            throw Error("distribution weight " + std::to_string(i) + " is negative or not finite");
        cdf_[i + 1] = cdf_[i] + weights[i];
    }
    total_ = cdf_.back();
    if (total_ > 0) {
        for (size_t i = 0; i < weights.size(); ++i) pmf_[i] = weights[i] / total_;
        for (double& c : cdf_) c /= total_;
        cdf_.back() = 1.0;
    }
}

size_t DiscreteDistribution::sampleReuse(double& u) const {
    // First bin whose upper CDF value exceeds u, skipping zero-probability bins.
    auto it = std::upper_bound(cdf_.begin() + 1, cdf_.end(), u);
    size_t i = std::min<size_t>(size_t(it - cdf_.begin()) - 1, pmf_.size() - 1);
    while (pmf_[i] == 0 && i + 1 < pmf_.size()) ++i;
    while (pmf_[i] == 0 && i > 0) --i;
    u = std::clamp((u - cdf_[i]) / pmf_[i], 0.0, std::nextafter(1.0, 0.0));
    return i;
}

std::vector<size_t> systematicResample(std::span<const double> weights, size_t n, double offset) {
    double total = 0;
    for (size_t i = 0; i < weights.size(); ++i) {
        if (!(weights[i] >= 0) || !std::isfinite(weights[i]))
            throw Error("resampling weight " + std::to_string(i) + " is negative or not finite");
        total += weights[i];
    }
    if (!(total > 0) || !std::isfinite(total)) throw Error("resampling weights that sum to 0 or overflow");
    std::vector<size_t> out;
    out.reserve(n);
    size_t i = 0, lastPositive = 0;
    double upper = weights[0]; // the weights' sum through index i, added in DiscreteDistribution's order
    for (size_t j = 0; j < n; ++j) {
        // The draw DiscreteDistribution::sample((j + offset) / n) makes, rounding included: the first index
        // whose normalized CDF value exceeds the position, zero weights skipped.
        const double u = (double(j) + offset) / double(n);
        while (i + 1 < weights.size() && (upper / total <= u || weights[i] == 0)) {
            if (weights[i] > 0) lastPositive = i;
            upper += weights[++i];
        }
        // Positions at the end of the CDF can reach trailing zero weights: the last positive one is drawn.
        out.push_back(weights[i] > 0 ? i : lastPositive);
    }
    return out;
}

Distribution2D::Distribution2D(std::span<const double> values, int width, int height) : width_(width), height_(height) {
    if (width <= 0 || height <= 0 || values.size() != size_t(width) * size_t(height))
        throw Error("Distribution2D: table size does not match its dimensions");
    std::vector<double> rowSums(height);
    rows_.reserve(height);
    for (int y = 0; y < height; ++y) {
        rows_.emplace_back(values.subspan(size_t(y) * width, width));
        rowSums[y] = rows_.back().total();
    }
    marginal_ = DiscreteDistribution(rowSums);
}

Vec2 Distribution2D::sample(const Vec2& u, double& pdf) const {
    double v = u.y;
    const size_t row = marginal_.sampleReuse(v);
    double w = u.x;
    const size_t col = rows_[row].sampleReuse(w);
    pdf = marginal_.pmf(row) * rows_[row].pmf(col) * double(width_) * double(height_);
    return {(double(col) + w) / width_, (double(row) + v) / height_};
}

double Distribution2D::pdf(const Vec2& p) const {
    if (marginal_.empty()) return 0;
    const int col = std::clamp(int(p.x * width_), 0, width_ - 1);
    const int row = std::clamp(int(p.y * height_), 0, height_ - 1);
    return marginal_.pmf(row) * rows_[row].pmf(col) * double(width_) * double(height_);
}

} // namespace lt
