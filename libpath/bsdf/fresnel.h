// Fresnel reflectance of smooth interfaces: the one place for this math.
#pragma once

#include "math/spectrum.h"

namespace lt {

// Exact unpolarized Fresnel reflectance of a dielectric interface (Born & Wolf; the same function as
// Mitsuba 0.5 fresnelDielectricExt). cosThetaI is signed against the normal, which points to the
// exterior: positive when the incident direction is on the exterior side. eta = eta_interior /
// eta_exterior. cosThetaT receives the signed cosine of the transmitted direction (opposite sign to
// cosThetaI; 0 on total internal reflection, where the reflectance is 1).
[[nodiscard]] double fresnelDielectric(double cosThetaI, double eta, double& cosThetaT);
[[nodiscard]] double fresnelDielectric(double cosThetaI, double eta);

// Exact Fresnel reflectance of a conductor with complex index eta + i k per RGB channel, relative to
// the exterior medium (the formula of Mitsuba 0.5 fresnelConductorExact; Born & Wolf). cosThetaI is
// clamped to [0, 1]. Guarded against the 0/0 of the p-polarized term at normal incidence on a perfect
// mirror (eta = k = 0).
[[nodiscard]] Spectrum fresnelConductor(double cosThetaI, const Spectrum& eta, const Spectrum& k);

// Diffuse Fresnel reflectance Fdr(eta) = 2 int_0^1 F(mu, eta) mu dmu: the reflectance of the
// interface under uniform (cosine-weighted) illumination from the side where the relative index is
// eta. Integrated numerically (composite Simpson in a variable that removes the kink at the critical
// angle), so the identity 1 - Fdr(1/eta) = (1 - Fdr(eta)) / eta^2 holds to ~1e-9, which makes the
// plastic model exactly energy conserving for a white base.
[[nodiscard]] double fresnelDiffuseReflectance(double eta);

} // namespace lt
