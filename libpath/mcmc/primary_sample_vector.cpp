#include "mcmc/primary_sample_vector.h"

#include <cmath>

namespace lt {

double SmallStepKernel::mutate(double u, Pcg32& rng) const {
    const double xi = rng.nextDouble();
    const double offset = s2_ * std::exp(-logRatio_ * rng.nextDouble());
    double v = xi < 0.5 ? u + offset : u - offset;
    v -= std::floor(v);
    return v < 1.0 ? v : 0.0; // floor of a tiny negative number can round v up to exactly 1
}

double SmallStepKernel::mutate(double u, uint64_t n, Pcg32& rng) const {
    if (n <= ExactSteps) {
        for (uint64_t k = 0; k < n; ++k)
            u = mutate(u, rng);
        return u;
    }
    // E[offset^2] for offset = s2 exp(-L xi), L = ln(s2 / s1), xi uniform: s2^2 (1 - e^(-2L)) / (2L).
    const double variance = s2_ * s2_ * (1 - (s1_ * s1_) / (s2_ * s2_)) / (2 * logRatio_);
    double v = u + std::sqrt(variance * double(n)) * standardNormal(rng);
    v -= std::floor(v);
    return v < 1.0 ? v : 0.0;
}

PrimarySampleVector::PrimarySampleVector(Pcg32 rng, Pcg32 init, SmallStepKernel kernel)
    : rng_(rng), init_(init), kernel_(kernel) {}

void PrimarySampleVector::startIteration(bool largeStep) {
    initial_ = false;
    ++iteration_;
    changed_.clear();
    largeStep_ = largeStep;
    restart();
}

void PrimarySampleVector::accept() {
    if (largeStep_) lastLargeStep_ = iteration_;
}

void PrimarySampleVector::reject() {
    for (const size_t i : changed_) {
        x_[i].value = x_[i].backup;
        x_[i].modified = x_[i].backupModified;
    }
    changed_.clear();
    // In the textbook chain a rejected proposal leaves EVERY coordinate as it was, the unread ones too, so
    // the rejected iteration is no step they missed: it does not count (pbrt-v3's MLTSampler::Reject
    // does the same). Counting it gave coordinates unread for a while (a multiplexed chain's light
    // subpath while it uses camera-side strategies) one extra small step per rejection, an asymmetric
    // proposal: multiplexed MLT rendered a smooth metal sphere lit through a door ajar 20-30 % dark.
    --iteration_;
}

void PrimarySampleVector::restart() {
    for (auto& i : streamIndex_)
        i = 0;
    stream_ = 0;
}

void PrimarySampleVector::startStream(Stream s) { stream_ = int(s); }

double PrimarySampleVector::next1D() {
    const size_t index = streamIndex_[stream_]++ * StreamCount + size_t(stream_);
    return prepare(index).value;
}

double PrimarySampleVector::value(Stream s, size_t index) const {
    const size_t i = index * StreamCount + size_t(s);
    return i < x_.size() ? x_[i].value : 0.0;
}

PrimarySampleVector::Coordinate& PrimarySampleVector::prepare(size_t index) {
    if (index >= x_.size()) x_.resize(index + 1);
    Coordinate& c = x_[index];
    if (c.modified == iteration_) return c;
    if (!initial_) changed_.push_back(index);
    c.backup = c.value;
    c.backupModified = c.modified;
    if (c.modified == Never) {
        // A coordinate no evaluation has read yet: uniform, like every coordinate the sampler has not
        // looked at. The initial state draws from its own stream.
        c.value = initial_ ? init_.nextDouble() : rng_.nextDouble();
    } else if (largeStep_ || c.modified < lastLargeStep_) {
        c.value = rng_.nextDouble();
    } else {
        // The small steps of the iterations since the last change, this one included.
        c.value = kernel_.mutate(c.value, iteration_ - c.modified, rng_);
    }
    c.modified = iteration_;
    return c;
}

} // namespace lt
