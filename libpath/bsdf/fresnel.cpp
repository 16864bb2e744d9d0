#include "bsdf/fresnel.h"

#include <cmath>

#include "math/numeric.h"

namespace lt {

double fresnelDielectric(double cosThetaI, double eta, double& cosThetaT) {
    if (eta == 1) {
        cosThetaT = -cosThetaI;
        return 0;
    }
    // Snell with the relative index seen from the incident side: eta from outside, 1/eta from inside.
    const double scale = cosThetaI > 0 ? 1 / eta : eta;
    const double cosT2 = 1 - (1 - cosThetaI * cosThetaI) * scale * scale;
    if (cosT2 <= 0) {
        cosThetaT = 0;
        return 1;
    }
    const double ci = std::abs(cosThetaI), ct = std::sqrt(cosT2);
    // With eta1 cos_i and eta2 cos_t written for the side the light comes from; swapping sides swaps
    // the s and p formulas, which leaves their average unchanged, so one pair serves both sides.
    const double rs = (ci - eta * ct) / (ci + eta * ct);
    const double rp = (eta * ci - ct) / (eta * ci + ct);
    cosThetaT = cosThetaI > 0 ? -ct : ct;
    return 0.5 * (rs * rs + rp * rp);
}

double fresnelDielectric(double cosThetaI, double eta) {
    double cosThetaT;
    return fresnelDielectric(cosThetaI, eta, cosThetaT);
}

namespace {

double fresnelConductorChannel(double cosI, double eta, double k) {
    const double c2 = cosI * cosI, s2 = 1 - c2, s4 = s2 * s2;
    const double t1 = eta * eta - k * k - s2;
    const double a2pb2 = std::sqrt(t1 * t1 + 4 * k * k * eta * eta);
    const double a = safeSqrt(0.5 * (a2pb2 + t1));
    const double term1 = a2pb2 + c2, term2 = 2 * a * cosI;
    const double rs = term1 + term2 > 0 ? (term1 - term2) / (term1 + term2) : 1.0;
    const double term3 = a2pb2 * c2 + s4, term4 = term2 * s2;
    const double rp = term3 + term4 > 0 ? rs * (term3 - term4) / (term3 + term4) : rs;
    return std::clamp(0.5 * (rs + rp), 0.0, 1.0);
}

} // namespace

Spectrum fresnelConductor(double cosThetaI, const Spectrum& eta, const Spectrum& k) {
    const double c = std::clamp(cosThetaI, 0.0, 1.0);
    return {fresnelConductorChannel(c, eta.r, k.r), fresnelConductorChannel(c, eta.g, k.g),
            fresnelConductorChannel(c, eta.b, k.b)};
}

double fresnelDiffuseReflectance(double eta) {
    // Fdr = 2 int_0^1 F(mu) mu dmu. For eta < 1, F = 1 below the critical cosine muC (total internal
    // reflection) and the transmitted cosine eta sqrt(mu^2 - muC^2) has a square-root kink at muC, which
    // would cripple Simpson's rule. With s = sqrt(mu^2 - muC^2) (so mu dmu = s ds) the integrand of
    // the remaining piece is smooth: int_muC^1 F mu dmu = int_0^sqrt(1 - muC^2) F(mu(s)) s ds.
    const double muC2 = eta < 1 ? 1 - eta * eta : 0.0;
    const double sMax = std::sqrt(1 - muC2);
    constexpr int n = 2000; // even; error far below 1e-9 for this smooth integrand
    const double h = sMax / n;
    double sum = 0;
    for (int i = 0; i <= n; ++i) {
        const double s = i * h;
        const double w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
        sum += w * fresnelDielectric(std::sqrt(muC2 + s * s), eta) * s;
    }
    return 2 * (0.5 * muC2 + sum * h / 3);
}

} // namespace lt
