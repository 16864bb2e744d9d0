// The BSDF at a surface point in world space, with the two rules that shading normals require
// (Veach thesis, Sec. 5.3): the adjoint correction for importance transport and the geometric-side test
// against light leaks. Path construction (sampling/, manifold/, gradient/) calls this, never the local
// Bsdf directly, so the rules live in one place.
//
// Convention: the path integral (Veach 1997; Jakob & Marschner 2012, Eq. 4) uses GEOMETRIC normals in G,
// so eval() returns the effective BSDF that is to be multiplied by the geometric cosine |wo.ng| (or
// enter f(x) next to a G built from geometric normals). Veach's shading-normal BSDF (thesis Sec. 5.3)
// rescales f_s by the ratio of shading to geometric cosine of the direction the LIGHT arrives from:
//   Radiance   (light arrives along wo): f = f_s(wi, wo) |wo.ns| / |wo.ng|
//   Importance (light arrives along wi): f = f_s(wi, wo) |wi.ns| / |wi.ng|     (adjoint, Eq. 5.21)
// The two differ by the factor |wi.ns| |wo.ng| / (|wi.ng| |wo.ns|), which is exactly pbrt-v3's
// CorrectShadingNormal: f |wo.ng| here equals f_s |wo.ns| times that factor in Importance mode. A
// sample's weight (f cos / pdf) is therefore the local weight, times the factor in Importance mode.
//
// Geometric-side test: reflection or transmission is decided by the geometric normal. If the shading
// normal classifies (wi, wo) differently (one says reflection, the other transmission), the value is 0
// and sample() rejects: otherwise light leaks through the surface or a reflection appears on the wrong
// side (Veach thesis Sec. 5.3). pdf() is the local sampling density unchanged, because sample() still
// generates those directions before rejecting them (MIS needs the generating density).
#pragma once

#include <optional>

#include "bsdf/bsdf.h"
#include "math/frame.h"

namespace lt {

struct WorldBsdf {
    const Bsdf& bsdf;
    Frame shading; // orthonormal, shading.n = shading normal
    Vec3 ng;       // unit geometric normal (either orientation)
    Vec2 uv;

    // The effective f described above; zero when the geometric and shading sides disagree or a
    // direction is tangent to either surface.
    [[nodiscard]] Spectrum eval(const Vec3& wiWorld, const Vec3& woWorld, Transport mode) const;
    // The local solid-angle density of wo given wi (non-delta lobes).
    [[nodiscard]] double pdf(const Vec3& wiWorld, const Vec3& woWorld) const;
    // A sample with wo in WORLD space and the corrected weight; nothing when rejected by the side test.
    [[nodiscard]] std::optional<BsdfSample> sample(const Vec3& wiWorld, Transport mode, double uLobe,
                                                   const Vec2& u) const;
    // deltaEval with world directions and the same corrections as sample().
    [[nodiscard]] std::optional<BsdfSample> deltaEval(const Vec3& wiWorld, const Vec3& woWorld, Transport mode) const;

    // The factor that turns the local value into the effective one: |wo.ns| / |wo.ng| (Radiance) or
    // |wi.ns| / |wi.ng| (Importance); 0 when a side test fails.
    [[nodiscard]] double shadingFactor(const Vec3& wiWorld, const Vec3& woWorld, Transport mode) const;
};

} // namespace lt
