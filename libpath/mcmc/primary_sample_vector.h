// The state of a primary-sample-space chain (Kelemen et al. 2002): an unbounded vector
// u of numbers in [0, 1) that a path sampler (our BDPT) consumes through the SampleGenerator interface,
// so the same sampler code runs under independent sampling and under the Markov chain.
//
// Coordinates are created and mutated lazily, when the sampler reads them (pbrt-v3's MLTSampler is the
// model). For the chain to be the textbook one, in which EVERY coordinate is mutated at every iteration
// with a symmetric kernel (the acceptance is then f*(u') / f*(u)), a coordinate read at iteration k
// receives all the mutations it missed since it was last touched: a fresh uniform value if a large step
// was accepted meanwhile (anything symmetric after a uniform draw stays uniform), otherwise the small
// steps of every missed iteration (SmallStepKernel::mutate(u, n, rng)). Only accepted iterations count:
// a rejected proposal changes no coordinate of the textbook chain. Three interleaved streams (camera, light,
// connection) keep the subpaths' numbers apart, so a longer camera subpath does not shift the light subpath's numbers.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "math/rng.h"
#include "sampling/sample_generator.h"

namespace lt {

// Kelemen's small step: u + or - s2 exp(-ln(s2 / s1) xi), wrapped to [0, 1) (Kelemen et al. 2002; MCMC survey,
// Sec. 4.1), with s1 = 1/1024 and s2 = 1/64 by default. Symmetric: the density of the offset depends on |offset| only.
class SmallStepKernel {
public:
    explicit SmallStepKernel(double s1 = 1.0 / 1024.0, double s2 = 1.0 / 64.0)
        : s1_(s1), s2_(s2), logRatio_(std::log(s2 / s1)) {}
    [[nodiscard]] double s1() const { return s1_; }
    [[nodiscard]] double s2() const { return s2_; }
    [[nodiscard]] double mutate(double u, Pcg32& rng) const;
    // n small steps at once. Up to ExactSteps they are drawn one by one; beyond, their sum is drawn as the
    // normal of the same variance n E[offset^2] (central limit: the excess kurtosis of one offset is
    // -0.2, of the sum -0.2 / n), wrapped. Still symmetric, and O(1): a coordinate unread for 10^5
    // iterations (a long path's light subpath while the chain uses short strategies) no longer costs
    // 10^5 exponentials when it is read again.
    static constexpr uint64_t ExactSteps = 16;
    [[nodiscard]] double mutate(double u, uint64_t n, Pcg32& rng) const;

private:
    double s1_, s2_;
    double logRatio_; // ln(s2 / s1), once: the small steps are most of a chain's random numbers
};

class PrimarySampleVector final : public SampleGenerator {
public:
    // `rng` draws the chain's mutations; `init` draws the coordinates of the initial state (a bootstrap
    // sample re-created from its own stream, so chains started from the same sample still differ).
    PrimarySampleVector(Pcg32 rng, Pcg32 init, SmallStepKernel kernel = SmallStepKernel());

    // Begin a proposal: iteration k + 1, a large step (all coordinates fresh) or a small step.
    void startIteration(bool largeStep);
    // End the proposal: keep the proposed coordinates, or restore those it changed.
    void accept();
    void reject();
    // Start reading from the first coordinate of every stream again (each evaluation of the sampler).
    void restart();

    void startStream(Stream s) override;
    [[nodiscard]] double next1D() override;
    [[nodiscard]] Vec2 next2D() override { // one virtual call for both numbers
        const double a = next1D();
        return {a, next1D()};
    }

    [[nodiscard]] uint64_t iteration() const { return iteration_; }
    [[nodiscard]] bool largeStep() const { return largeStep_; }
    [[nodiscard]] size_t dimension() const { return x_.size(); }
    // Coordinate `index` of stream `s` as it is now (tests).
    [[nodiscard]] double value(Stream s, size_t index) const;
    Pcg32& rng() { return rng_; }

private:
    static constexpr int StreamCount = 3;
    static constexpr uint64_t Never = ~uint64_t(0);
    struct Coordinate {
        double value = 0;
        uint64_t modified = Never; // iteration of the last change (Never: not created yet)
        double backup = 0;
        uint64_t backupModified = Never;
    };
    Coordinate& prepare(size_t index);

    Pcg32 rng_, init_;
    SmallStepKernel kernel_;
    std::vector<Coordinate> x_;
    std::vector<size_t> changed_;                // coordinates the current proposal changed: those reject() restores
    uint64_t iteration_ = 0, lastLargeStep_ = 0; // iteration_ counts accepted proposals and the current one
    bool initial_ = true;                        // no proposal yet: reading the initial state
    bool largeStep_ = true;
    int stream_ = 0;
    size_t streamIndex_[StreamCount] = {0, 0, 0};
};

} // namespace lt
