// A BSDF of delta lobes only (the smooth dielectric, the thin dielectric, the smooth conductor): for a pair of
// directions it has no value and no density (a delta lobe is reached only by sampling it, or asked for with
// deltaEval), and it is perfectly smooth. Its sample() and deltaEval() are its own.
#pragma once

#include "bsdf/bsdf.h"

namespace lt {

class DeltaBsdf : public Bsdf {
public:
    [[nodiscard]] Spectrum eval(const Vec3&, const Vec3&, const Vec2&, Transport) const final { return {}; }
    [[nodiscard]] double pdf(const Vec3&, const Vec3&, const Vec2&) const final { return 0; }
    [[nodiscard]] double roughness(const Vec2&) const final { return 0; }
};

} // namespace lt
