// Delta lobes of several BSDFs that reach the same direction (a blend of two mirrors, a mask's
// straight-through lobe over a nested BSDF that also transmits straight): one lobe whose coefficient is the
// sum of the parts' coefficients (weight x discrete probability, times the part's share of f) and whose
// probability is the sum of the probabilities with which each part samples it. Its weight is their ratio.
#pragma once

#include <optional>

#include "bsdf/bsdf.h"

namespace lt {

class DeltaLobeSum {
public:
    // A part's lobe at wo (from deltaEval), its share of f and the probability of choosing that part.
    void add(const BsdfSample& lobe, const Spectrum& share, double choice) {
        coefficient_ += lobe.weight * share * lobe.pdf;
        probability_ += choice * lobe.pdf;
        if (!first_) first_ = lobe;
    }
    // The summed lobe toward wo (the first part's lobe type and eta), or nothing when no part reaches it or
    // it carries nothing.
    [[nodiscard]] std::optional<BsdfSample> result(const Vec3& wo) const {
        if (!first_ || !(probability_ > 0)) return std::nullopt;
        BsdfSample s = *first_;
        s.wo = wo;
        s.pdf = probability_;
        s.weight = coefficient_ / probability_;
        if (!s.weight.isFinite() || s.weight.isBlack()) return std::nullopt;
        return s;
    }

private:
    Spectrum coefficient_;
    double probability_ = 0;
    std::optional<BsdfSample> first_;
};

} // namespace lt
