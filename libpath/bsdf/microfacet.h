// Anisotropic Beckmann and GGX microfacet distributions (Walter et al. 2007, "Microfacet Models for
// Refraction through Rough Surfaces"; Heitz 2014, "Understanding the Masking-Shadowing Function"):
// the normal distribution D(m), the Smith masking G1 and the separable G, and sampling of the
// distribution of visible normals with its density.
//
// Sampling choice: visible normals for both distributions. GGX uses Heitz 2018 ("Sampling the GGX
// Distribution of Visible Normals", JCGT 7(4)), closed form. Beckmann uses the stretch-sample-unstretch
// scheme of Heitz & d'Eon 2014 with the 1D slope CDF inverted numerically in the erf domain (the
// approach of Jakob 2014, "An Improved Visible Normal Sampling Routine for the Beckmann Distribution"),
// safeguarded Newton-bisection so it cannot diverge. Why not D(m) cos(m) sampling: at 89 degrees
// incidence its weight G |i.m| / (|i.n| |m.n|) reaches 1/cos(89 deg) ~ 57 and half the samples land on
// back-facing microfacets, which is what breaks Markov chains and BDPT at grazing angles; the visible
// normal weight is G2/G1 <= 1 for every alpha and angle. At alpha 1e-3 the stretched incidence is
// near normal (tan 89 deg * 1e-3 ~ 0.06), where both samplers are closed form in effect.
#pragma once

#include "math/vec.h"

namespace lt {

enum class MicrofacetType { Beckmann, GGX };

class MicrofacetDistribution {
public:
    // alphaU along the local x (s) axis, alphaV along y (t). Clamped below at 1e-4 (the smallest
    // roughness the project supports and tests), where D at the peak is still finite (~3e7).
    MicrofacetDistribution(MicrofacetType type, double alphaU, double alphaV);

    [[nodiscard]] MicrofacetType type() const { return type_; }
    [[nodiscard]] double alphaU() const { return alphaU_; }
    [[nodiscard]] double alphaV() const { return alphaV_; }
    // Beckmann-equivalent roughness (bsdf.h roughness()): the smaller alpha (the sharper direction),
    // GGX divided by sqrt(2) (equal curvature of D at the peak).
    [[nodiscard]] double beckmannEquivalentAlpha() const;

    // D(m) in 1/sr for m in the upper hemisphere, 0 below.
    [[nodiscard]] double D(const Vec3& m) const;
    // Smith masking of direction v by microfacets with normal m, with the side test chi+(v.m / v.n):
    // v and its microfacet must face the same side of the macro surface (Walter 2007 Eq. 7). v may lie
    // on either side of the surface.
    [[nodiscard]] double G1(const Vec3& v, const Vec3& m) const;
    // Separable shadowing-masking G1(i, m) G1(o, m) (Walter 2007 Eq. 23).
    [[nodiscard]] double G(const Vec3& i, const Vec3& o, const Vec3& m) const;

    // Sample a normal m (upper hemisphere) from the visible-normal distribution
    // D_v(m) = G1(v, m) max(0, v.m) D(m) / v.z seen from v; v on the lower side is mirrored through the
    // origin (v -> -v, as Mitsuba and Walter do for refraction from inside). May return a normal with
    // m.z == 0 in round-off corners; its pdf is then 0 and the caller rejects it.
    [[nodiscard]] Vec3 sampleVisible(const Vec3& v, const Vec2& u) const;
    // The density, in solid angle of m, with which sampleVisible(v, .) produces m.
    [[nodiscard]] double pdfVisible(const Vec3& v, const Vec3& m) const;

private:
    // Smith Lambda(v) for the projected roughness of v (Heitz 2014 Eq. 72 for Beckmann, 86 for GGX).
    [[nodiscard]] double smithLambda(const Vec3& v) const;
    // Sample the slopes of the visible normals of the unit-roughness distribution for an incident
    // direction with polar angle theta in the stretched space, azimuth along +x (Heitz & d'Eon 2014).
    [[nodiscard]] Vec2 sampleVisibleSlopesBeckmann11(double cosTheta, const Vec2& u) const;

    MicrofacetType type_;
    double alphaU_, alphaV_;
};

} // namespace lt
