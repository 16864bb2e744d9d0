#include "bsdf/roughplastic.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "bsdf/fresnel.h"
#include "bsdf/half_vector.h"
#include "bsdf/ior_presets.h"
#include "math/constants.h"
#include "util/error.h"
#include "math/numeric.h"
#include "math/warp.h"

namespace lt {

RoughPlastic::RoughPlastic(RoughPlasticParams params)
    : p_(std::move(params)), distr_(p_.distribution, p_.alpha, p_.alpha) {
    checkIorPair("roughplastic", p_.intIOR, p_.extIOR);
    if (!(p_.alpha > 0) || !std::isfinite(p_.alpha)) throw Error("roughplastic: alpha must be positive and finite");
    if (!p_.specularReflectance || !p_.diffuseReflectance) throw Error("roughplastic: null texture");
    eta_ = p_.intIOR / p_.extIOR;

    // A(mu) = E over visible normals of the sample weight F(wi.m) G1(wo, m) (roughconductor.cpp derives
    // it), integrated over the sampler's unit square by a K x K midpoint rule after the substitution
    // u = 3 v^2 - 2 v^3 (weight 6 v (1 - v) per axis), which flattens the inverse-erf end-point
    // singularities of the Beckmann sampler so the rule converges at its O(1/K^2) rate (error below
    // 3e-4 at K = 32 against K = 512, for alpha 0.3-1 and incidence up to 89 degrees). Nodes are uniform
    // in t = sqrt(mu), dense near grazing incidence where T changes fastest; the first is taken at
    // mu = 1e-4, not at exactly grazing incidence where the visible-normal density is undefined.
    constexpr int K = 32;
    const auto smooth = [](double v) { return std::pair{v * v * (3 - 2 * v), 6 * v * (1 - v)}; };
    for (int j = 0; j < TableSize; ++j) {
        const double mu = std::max(sqr(double(j) / (TableSize - 1)), 1e-4);
        const Vec3 wi(safeSqrt(1 - mu * mu), 0, mu);
        double albedo = 0;
        for (int a = 0; a < K; ++a)
            for (int b = 0; b < K; ++b) {
                const auto [ua, wa] = smooth((a + 0.5) / K);
                const auto [ub, wb] = smooth((b + 0.5) / K);
                const Vec3 m = distr_.sampleVisible(wi, Vec2(ua, ub));
                const Vec3 wo = reflect(wi, m);
                if (wo.z > 0) albedo += wa * wb * fresnelDielectric(dot(wi, m), eta_) * distr_.G1(wo, m);
            }
        transmittance_[j] = std::clamp(1 - albedo / (K * K), 0.0, 1.0);
    }
    // 2 int_0^1 T mu dmu = 4 int_0^1 T(t) t^3 dt of the piecewise-linear T(t), exactly.
    double avg = 0;
    const double h = 1.0 / (TableSize - 1);
    for (int j = 0; j + 1 < TableSize; ++j) {
        const double t0 = j * h, t1 = t0 + h, T0 = transmittance_[j], T1 = transmittance_[j + 1];
        const double i3 = (std::pow(t1, 4) - std::pow(t0, 4)) / 4;          // int t^3
        const double i4 = (std::pow(t1, 5) - std::pow(t0, 5)) / 5 - t0 * i3; // int (t - t0) t^3
        avg += 4 * (T0 * i3 + (T1 - T0) / h * i4);
    }
    fdrInt_ = 1 - avg / (eta_ * eta_);

    const double s = p_.specularReflectance->average().luminance();
    const double d = p_.diffuseReflectance->average().luminance();
    specularSamplingWeight_ = s + d > 0 ? s / (s + d) : 0.5;
}

double RoughPlastic::coatTransmittance(double mu) const {
    // !(mu > 0) also takes a NaN to 0: std::clamp passes it through, and int(NaN) indexes anywhere.
    const double x = std::sqrt(mu > 0 ? std::min(mu, 1.0) : 0.0) * (TableSize - 1);
    const int j = std::min(int(x), TableSize - 2);
    const double t = x - j;
    return (1 - t) * transmittance_[j] + t * transmittance_[j + 1];
}

double RoughPlastic::specularProbability(double Ti) const {
    // Mitsuba 0.5: the coat's reflectance 1 - T weighted by the average specular vs diffuse reflectance.
    const double a = (1 - Ti) * specularSamplingWeight_, b = Ti * (1 - specularSamplingWeight_);
    return a + b > 0 ? a / (a + b) : 0.0;
}

Spectrum RoughPlastic::eval(const Vec3& wi, const Vec3& wo, const Vec2& uv, Transport) const {
    if (wi.z <= 0 || wo.z <= 0) return {};
    Spectrum result;
    if (const auto h = halfVector(wi, wo, 1)) {
        const double DG = distr_.D(*h) * distr_.G(wi, wo, *h);
        if (DG > 0)
            result = p_.specularReflectance->eval(uv) *
                     (fresnelDielectric(dot(wi, *h), eta_) * DG / (4 * wi.z * wo.z));
    }
    Spectrum diff = p_.diffuseReflectance->eval(uv);
    if (p_.nonlinear)
        diff = diff / (Spectrum(1.0) - diff * fdrInt_);
    else
        diff /= 1 - fdrInt_;
    result += diff * (coatTransmittance(wi.z) * coatTransmittance(wo.z) * InvPi / (eta_ * eta_));
    return result;
}

double RoughPlastic::pdf(const Vec3& wi, const Vec3& wo, const Vec2&) const {
    if (wi.z <= 0 || wo.z <= 0) return 0;
    const double pSpec = specularProbability(coatTransmittance(wi.z));
    double specPdf = 0;
    if (const auto h = halfVector(wi, wo, 1)) specPdf = distr_.pdfVisible(wi, *h) * halfVectorJacobian(*h, wi, wo, 1);
    const double pdf = pSpec * specPdf + (1 - pSpec) * warp::squareToCosineHemispherePdf(wo);
    return std::isfinite(pdf) ? pdf : 0.0;
}

std::optional<BsdfSample> RoughPlastic::sample(const Vec3& wi, const Vec2& uv, Transport mode, double uLobe,
                                               const Vec2& u) const {
    if (wi.z <= 0) return std::nullopt;
    const double pSpec = specularProbability(coatTransmittance(wi.z));
    BsdfSample s;
    if (uLobe < pSpec) {
        s.wo = reflect(wi, distr_.sampleVisible(wi, u));
        s.lobe = LobeGlossy | LobeReflection;
    } else {
        s.wo = warp::squareToCosineHemisphere(u);
        s.lobe = LobeDiffuse | LobeReflection;
    }
    if (s.wo.z <= 0) return std::nullopt;
    // Two lobes overlap, so the weight uses the full mixture density (one-sample MIS over the lobes).
    s.pdf = pdf(wi, s.wo, uv);
    if (!(s.pdf > 0)) return std::nullopt;
    s.weight = eval(wi, s.wo, uv, mode) * (s.wo.z / s.pdf);
    if (!s.weight.isFinite()) return std::nullopt;
    return s;
}

} // namespace lt
