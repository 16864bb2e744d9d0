// Discrete and piecewise-constant distributions, built once from non-negative weights and sampled by
// inverting the CDF. Light selection, triangle selection by area and environment-map importance
// sampling all use these.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "math/vec.h"

namespace lt {

class DiscreteDistribution {
public:
    DiscreteDistribution() = default;
    // Weights must be finite and >= 0; throws lt::Error otherwise. An all-zero set is allowed and
    // reports empty() (nothing can be sampled).
    explicit DiscreteDistribution(std::span<const double> weights);

    [[nodiscard]] bool empty() const { return total_ <= 0; }
    [[nodiscard]] size_t size() const { return pmf_.size(); }
    [[nodiscard]] double total() const { return total_; }
    [[nodiscard]] double pmf(size_t i) const { return pmf_[i]; }
    // Returns the index; u is reused: on return it is uniform in [0,1) again within the chosen bin.
    size_t sampleReuse(double& u) const;
    [[nodiscard]] size_t sample(double u) const {
        double v = u;
        return sampleReuse(v);
    }

private:
    std::vector<double> cdf_, pmf_;
    double total_ = 0;
};

// Systematic resampling (Kitagawa 1996): n indices drawn in proportion to `weights`, at the positions
// (j + offset) / n, j = 0 .. n-1, of their normalized CDF, with offset in [0, 1); index i is drawn
// floor(n w_i / W) or ceil(n w_i / W) times, never when its weight is 0. Returns the indices in increasing
// order, each the one DiscreteDistribution(weights).sample((j + offset) / n) returns, rounding included,
// in one pass and without a copy of the weights: a Markov-chain start-up resamples millions of samples.
// Weights must be finite and >= 0, not all 0; throws lt::Error otherwise.
[[nodiscard]] std::vector<size_t> systematicResample(std::span<const double> weights, size_t n, double offset);

// Piecewise-constant density on [0,1]^2 from a (width x height) table of non-negative values, as in
// pbrt's Distribution2D: marginal over rows, conditional within a row.
class Distribution2D {
public:
    Distribution2D() = default;
    Distribution2D(std::span<const double> values, int width, int height);
    // Sample a point in [0,1)^2 and its density with respect to area on [0,1]^2.
    [[nodiscard]] Vec2 sample(const Vec2& u, double& pdf) const;
    [[nodiscard]] double pdf(const Vec2& p) const;
    [[nodiscard]] bool empty() const { return marginal_.empty(); }

private:
    int width_ = 0, height_ = 0;
    std::vector<DiscreteDistribution> rows_;
    DiscreteDistribution marginal_;
};

} // namespace lt
