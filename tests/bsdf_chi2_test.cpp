// Chi-square goodness-of-fit of every BSDF's sample() against its pdf(), in the spirit of Mitsuba's
// chi2test: histogram many samples, integrate the pdf over the same cells numerically, pool cells with
// an expected count below 5, and reject at a Bonferroni-corrected significance level.
//
// Binning. A fixed theta/phi grid cannot resolve a lobe of width 1e-3. Every continuous lobe here is
// (or contains) a microfacet lobe, which is compact in half-vector space at any incidence angle: the
// sampled density of h is D_visible(h) times a Fresnel probability, whose width is alpha for reflection
// AND refraction. So a sample wo is binned through its generalized half vector h (bsdf/half_vector.h,
// eta = 1 for wo on wi's side, eta_wo/eta_wi on the other side, one histogram per side), in slope
// coordinates p = (h.x/h.z, h.y/h.z) scaled by (sU, sV) (the roughness; 1 for diffuse lobes),
// polar (r, phi), and x = sqrt(r) / (1 + sqrt(r)). This map covers the whole hemisphere of wo once, puts
// a lobe of scale alpha in the middle of [0, 1), keeps broad diffuse lobes at alpha 1e-3 inside a few
// bins near x = 1 with a bounded density, and its density in (x, phi) stays bounded at both ends.
// The expected count of a bin is N times the integral over (x, phi) of
//   pdf(wi, wo(h)) |d omega_o / d omega_h| h.z^3 sU sV r dr/dx,
// with wo(h) the reflection or refraction of wi about h; integrated by adaptive midpoint cubature
// (4x4 against 8x8, bisected to depth 3 where they disagree, e.g. across the horizon or a TIR edge).
// Delta samples, rejected samples and directions no bin holds form one more cell whose expected count is
// N (1 - sum of the bin integrals): this also tests that pdf() integrates to the probability of the
// continuous lobes.
#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "bsdf/blend.h"
#include "bsdf/bump_mapped.h"
#include "bsdf/conductor.h"
#include "bsdf/dielectric.h"
#include "bsdf/diffuse.h"
#include "bsdf/mask.h"
#include "bsdf/half_vector.h"
#include "bsdf/phong.h"
#include "bsdf/plastic.h"
#include "bsdf/roughconductor.h"
#include "bsdf/roughdielectric.h"
#include "bsdf/roughplastic.h"
#include "bsdf/twosided.h"
#include "bsdf/ward.h"
#include "math/constants.h"
#include "math/rng.h"

using namespace lt;

namespace {

// Regularized upper incomplete gamma Q(a, x) (Numerical Recipes 6.2: series for x < a + 1, Lentz's
// continued fraction otherwise); the chi-square p-value is Q(dof / 2, chi2 / 2).
double gammaQ(double a, double x) {
    if (x <= 0) return 1;
    const double lnPre = -x + a * std::log(x) - std::lgamma(a);
    if (x < a + 1) {
        double sum = 1 / a, term = sum;
        for (int n = 1; n < 100000; ++n) {
            term *= x / (a + n);
            sum += term;
            if (std::abs(term) < std::abs(sum) * 1e-15) break;
        }
        return 1 - sum * std::exp(lnPre);
    }
    const double tiny = 1e-300;
    double b = x + 1 - a, c = 1 / tiny, d = 1 / b, h = d;
    for (int i = 1; i < 100000; ++i) {
        const double an = -i * (i - a);
        b += 2;
        d = an * d + b;
        if (std::abs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::abs(c) < tiny) c = tiny;
        d = 1 / d;
        const double delta = d * c;
        h *= delta;
        if (std::abs(delta - 1) < 1e-15) break;
    }
    return std::exp(lnPre) * h;
}

Vec3 dirFromAngles(double thetaDeg, double phiDeg, bool below = false) {
    const double t = degToRad(thetaDeg), p = degToRad(phiDeg);
    return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), below ? -std::cos(t) : std::cos(t)};
}

template <class T, class P> std::shared_ptr<const Bsdf> makeBsdf(const P& params) {
    return std::make_shared<T>(params);
}

struct Config {
    std::string name;
    // Built only when the configuration runs (rough plastic precomputes a table in its constructor).
    std::function<std::shared_ptr<const Bsdf>()> make;
    Vec3 wi;
    double sU = 1, sV = 1; // slope scales of the bins
    Transport mode = Transport::Radiance;
};

constexpr int NX = 20, NPHI = 32;
constexpr int NSamples = 100000;
const Vec2 UV(0.5, 0.5);

struct Binning {
    const Config& c;
    const Bsdf& bsdf;
    double etaT; // eta_wo / eta_wi for the transmission side (1 when the BSDF does not refract)

    // Outgoing direction and density factor for cell coordinates (x, phi) on side t (0 reflection,
    // 1 transmission); 0 when wo does not exist or lands on the other side.
    [[nodiscard]] double density(int side, double x, double phi) const {
        const double q = x / (1 - x), r = q * q; // sqrt(r) = x / (1 - x)
        const double drdx = 2 * q / sqr(1 - x);
        const Vec3 h = normalize(Vec3(c.sU * r * std::cos(phi), c.sV * r * std::sin(phi), 1));
        std::optional<Vec3> wo;
        if (side == 0)
            wo = reflect(c.wi, h);
        else
            wo = refract(c.wi, h, etaT);
        if (!wo || wo->z == 0 || ((wo->z * c.wi.z > 0) != (side == 0))) return 0;
        const double J = halfVectorJacobian(h, c.wi, *wo, side == 0 ? 1 : etaT);
        if (!(J > 0)) return 0;
        const double p = bsdf.pdf(c.wi, *wo, UV);
        return p / J * h.z * h.z * h.z * c.sU * c.sV * r * drdx;
    }

    [[nodiscard]] double midpoint(int side, double x0, double x1, double p0, double p1, int n) const {
        double sum = 0;
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j)
                sum += density(side, x0 + (i + 0.5) * (x1 - x0) / n, p0 + (j + 0.5) * (p1 - p0) / n);
        return sum * (x1 - x0) * (p1 - p0) / (n * n);
    }

    [[nodiscard]] double integrate(int side, double x0, double x1, double p0, double p1, int depth) const {
        const double coarse = midpoint(side, x0, x1, p0, p1, 4), fine = midpoint(side, x0, x1, p0, p1, 8);
        if (depth == 0 || std::abs(fine - coarse) <= 1e-3 * std::abs(fine) + 1e-12) return fine;
        const double xm = 0.5 * (x0 + x1), pm = 0.5 * (p0 + p1);
        return integrate(side, x0, xm, p0, pm, depth - 1) + integrate(side, xm, x1, p0, pm, depth - 1) +
               integrate(side, x0, xm, pm, p1, depth - 1) + integrate(side, xm, x1, pm, p1, depth - 1);
    }

    // The cell of a continuous sample, or -1.
    [[nodiscard]] int cell(const Vec3& wo) const {
        const int side = wo.z * c.wi.z > 0 ? 0 : 1;
        const auto h = halfVector(c.wi, wo, side == 0 ? 1 : etaT);
        if (!h || !(h->z > 0)) return -1;
        const double px = h->x / h->z / c.sU, py = h->y / h->z / c.sV;
        const double r = std::sqrt(px * px + py * py);
        const double x = std::sqrt(r) / (1 + std::sqrt(r));
        double phi = std::atan2(py, px);
        if (phi < 0) phi += TwoPi;
        const int ix = std::min(int(x * NX), NX - 1), ip = std::min(int(phi / TwoPi * NPHI), NPHI - 1);
        return side * NX * NPHI + ix * NPHI + ip;
    }
};

struct Chi2Result {
    double pValue = 1;
    int dof = 0;
    int weightMismatches = 0;
    double continuousMass = 0;
    std::string worstWeight;
};

Chi2Result runChi2(const Config& config, uint64_t seed) {
    const auto bsdf = config.make();
    const Config& c = config;
    double etaT = 1;
    if (const auto e = bsdf->eta()) etaT = c.wi.z > 0 ? e->interior / e->exterior : e->exterior / e->interior;
    const Binning bins{c, *bsdf, etaT};
    const int nCells = 2 * NX * NPHI;

    std::vector<double> expected(nCells + 1, 0.0), observed(nCells + 1, 0.0);
    double mass = 0;
    for (int side = 0; side < 2; ++side) {
        if (side == 1 && !bsdf->hasTransmission()) continue;
        for (int ix = 0; ix < NX; ++ix)
            for (int ip = 0; ip < NPHI; ++ip) {
                const double m = bins.integrate(side, double(ix) / NX, double(ix + 1) / NX, TwoPi * ip / NPHI,
                                                TwoPi * (ip + 1) / NPHI, 3);
                expected[side * NX * NPHI + ix * NPHI + ip] = m * NSamples;
                mass += m;
            }
    }
    expected[nCells] = std::max(0.0, 1 - mass) * NSamples;

    Chi2Result res;
    res.continuousMass = mass;
    Pcg32 rng(seed, 7);
    for (int i = 0; i < NSamples; ++i) {
        const double uLobe = rng.nextDouble();
        const Vec2 u(rng.nextDouble(), rng.nextDouble());
        const auto s = bsdf->sample(c.wi, UV, c.mode, uLobe, u);
        if (!s || (s->lobe & LobeDelta)) {
            observed[nCells] += 1;
            continue;
        }
        const int k = bins.cell(s->wo);
        observed[k < 0 ? nCells : k] += 1;
        // The sample's weight and pdf must be what eval() and pdf() say (non-delta lobes).
        const double pdf = bsdf->pdf(c.wi, s->wo, UV);
        const Spectrum expectW = bsdf->eval(c.wi, s->wo, UV, c.mode) * (std::abs(s->wo.z) / pdf);
        const double tol = 1e-6 * std::max(1.0, expectW.maxValue());
        const bool ok = std::abs(pdf - s->pdf) <= 1e-6 * pdf && std::abs(expectW.r - s->weight.r) <= tol &&
                        std::abs(expectW.g - s->weight.g) <= tol && std::abs(expectW.b - s->weight.b) <= tol;
        if (!ok) {
            if (res.weightMismatches == 0) {
                std::ostringstream os;
                os << "wo=(" << s->wo.x << "," << s->wo.y << "," << s->wo.z << ") pdf " << s->pdf << " vs " << pdf
                   << ", weight " << s->weight.r << " vs " << expectW.r;
                res.worstWeight = os.str();
            }
            ++res.weightMismatches;
        }
    }

    // Pool the cells with expected count < 5 into one (Mitsuba chi2test), drop it if still < 5.
    double chi2 = 0, pooledE = 0, pooledO = 0;
    int cells = 0;
    for (int k = 0; k <= nCells; ++k) {
        if (expected[k] < 5) {
            pooledE += expected[k];
            pooledO += observed[k];
            continue;
        }
        chi2 += sqr(observed[k] - expected[k]) / expected[k];
        ++cells;
    }
    if (pooledE >= 5) {
        chi2 += sqr(pooledO - pooledE) / pooledE;
        ++cells;
    } else if (pooledO > 20) {
        // Many samples where the pdf says almost none: a gross mismatch, fail outright.
        res.pValue = 0;
        return res;
    }
    res.dof = cells - 1;
    res.pValue = res.dof > 0 ? gammaQ(0.5 * res.dof, 0.5 * chi2) : 1.0;
    return res;
}

std::vector<Config> makeConfigs() {
    std::vector<Config> configs;
    const auto tex = [](double v) { return std::make_shared<ConstantTexture>(Spectrum(v)); };
    const double thetas[] = {0, 60, 89};
    const double alphas[] = {1e-3, 0.05, 0.3, 1};
    const MicrofacetType types[] = {MicrofacetType::Beckmann, MicrofacetType::GGX};
    const auto typeName = [](MicrofacetType t) { return t == MicrofacetType::GGX ? "ggx" : "beckmann"; };

    for (double th : {0.0, 45.0, 89.0})
        configs.push_back({"diffuse th=" + std::to_string(th),
                           [=] { return makeBsdf<Diffuse>(DiffuseParams{tex(0.7)}); },
                           dirFromAngles(th, 20)});
    for (MicrofacetType t : types)
        for (double a : alphas)
            for (double th : thetas) {
                RoughConductorParams p;
                p.distribution = t;
                p.alphaU = p.alphaV = a;
                configs.push_back({std::string("roughconductor ") + typeName(t) + " a=" + std::to_string(a) +
                                       " th=" + std::to_string(th),
                                   [=] { return makeBsdf<RoughConductor>(p); }, dirFromAngles(th, 35), a, a});
            }
    for (MicrofacetType t : types) {
        RoughConductorParams p;
        p.distribution = t;
        p.alphaU = 0.05;
        p.alphaV = 0.4;
        configs.push_back({std::string("roughconductor aniso ") + typeName(t),
                           [=] { return makeBsdf<RoughConductor>(p); },
                           dirFromAngles(70, 30), 0.05, 0.4});
        TwoSidedParams tp;
        tp.front = std::make_shared<RoughConductor>(p);
        configs.push_back({std::string("twosided(roughconductor) back ") + typeName(t),
                           [=] { return makeBsdf<TwoSided>(tp); }, dirFromAngles(50, 110, true), 0.05, 0.4});
    }
    for (MicrofacetType t : types)
        for (double a : {1e-3, 0.1, 1.0})
            for (double th : thetas)
                for (bool below : {false, true})
                    for (Transport mode : {Transport::Radiance, Transport::Importance}) {
                        if (mode == Transport::Importance && th != 60) continue; // pdf is mode-independent
                        RoughDielectricParams p;
                        p.distribution = t;
                        p.alphaU = p.alphaV = a;
                        configs.push_back({std::string("roughdielectric ") + typeName(t) + " a=" + std::to_string(a) +
                                               " th=" + std::to_string(th) + (below ? " inside" : " outside") +
                                               (mode == Transport::Importance ? " importance" : ""),
                                           [=] { return makeBsdf<RoughDielectric>(p); },
                                           dirFromAngles(th, 15, below), a, a, mode});
                    }
    for (double eta : {1.0001, 4.0})
        for (bool below : {false, true}) {
            RoughDielectricParams p;
            p.distribution = MicrofacetType::GGX;
            p.alphaU = 0.3;
            p.alphaV = 0.1;
            p.intIOR = eta;
            p.extIOR = 1;
            configs.push_back({"roughdielectric aniso eta=" + std::to_string(eta) + (below ? " inside" : " outside"),
                               [=] { return makeBsdf<RoughDielectric>(p); }, dirFromAngles(45, 60, below), 0.3, 0.1});
        }
    for (double th : thetas) {
        PlasticParams p;
        p.diffuseReflectance = tex(0.6);
        configs.push_back(
            {"plastic th=" + std::to_string(th), [=] { return makeBsdf<Plastic>(p); }, dirFromAngles(th, 0)});
    }
    for (MicrofacetType t : types)
        for (double a : {1e-3, 0.1, 1.0})
            for (double th : thetas) {
                RoughPlasticParams p;
                p.distribution = t;
                p.alpha = a;
                p.diffuseReflectance = tex(0.6);
                configs.push_back({std::string("roughplastic ") + typeName(t) + " a=" + std::to_string(a) +
                                       " th=" + std::to_string(th),
                                   [=] { return makeBsdf<RoughPlastic>(p); }, dirFromAngles(th, 80), a, a});
            }
    for (double n : {1.0, 30.0, 2000.0})
        for (double th : thetas) {
            PhongParams p;
            p.exponent = tex(n);
            const double a = std::sqrt(2 / (n + 2)); // bins scaled to the lobe's Beckmann-equivalent width
            configs.push_back({"phong n=" + std::to_string(n) + " th=" + std::to_string(th),
                               [=] { return makeBsdf<Phong>(p); }, dirFromAngles(th, 40), a, a});
        }
    for (WardVariant variant : {WardVariant::Ward, WardVariant::WardDuer, WardVariant::Balanced})
        for (double th : thetas) {
            WardParams p;
            p.variant = variant;
            p.alphaU = tex(0.05);
            p.alphaV = tex(0.3);
            configs.push_back({"ward variant " + std::to_string(int(variant)) + " th=" + std::to_string(th),
                               [=] { return makeBsdf<Ward>(p); }, dirFromAngles(th, 65), 0.05, 0.3});
        }
    for (double th : thetas) {
        RoughConductorParams rc;
        rc.alphaU = rc.alphaV = 0.1;
        configs.push_back({"blendbsdf(diffuse, roughconductor) th=" + std::to_string(th),
                           [=] {
                               return makeBsdf<BlendBsdf>(BlendParams{
                                   tex(0.3), makeBsdf<Diffuse>(DiffuseParams{tex(0.8)}), makeBsdf<RoughConductor>(rc)});
                           },
                           dirFromAngles(th, 50), 0.3, 0.3});
        RoughDielectricParams rd;
        rd.alphaU = rd.alphaV = 0.3;
        for (bool below : {false, true})
            configs.push_back(
                {"blendbsdf(dielectric, roughdielectric) th=" + std::to_string(th) + (below ? " inside" : " outside"),
                 [=] {
                     return makeBsdf<BlendBsdf>(BlendParams{tex(0.5), makeBsdf<Dielectric>(DielectricParams{}),
                                                            makeBsdf<RoughDielectric>(rd)});
                 },
                 dirFromAngles(th, 50, below), 0.3, 0.3});
        configs.push_back({"bumpmap(roughconductor) th=" + std::to_string(th),
                           [=]() -> std::shared_ptr<const Bsdf> {
                               return std::make_shared<BumpMappedBsdf>(tex(0.2), makeBsdf<RoughConductor>(rc));
                           },
                           dirFromAngles(th, 50), 0.1, 0.1});
        configs.push_back({"mask(roughconductor) th=" + std::to_string(th),
                           [=] {
                               return makeBsdf<MaskBsdf>(MaskParams{tex(0.4), makeBsdf<RoughConductor>(rc)});
                           },
                           dirFromAngles(th, 50), 0.1, 0.1});
    }
    return configs;
}

// Runs the configurations whose name starts with one of the prefixes. The test is split by family so
// CTest can run the families in parallel; the Bonferroni correction is over all configurations.
void runFamily(std::initializer_list<const char*> prefixes) {
    const std::vector<Config> configs = makeConfigs();
    // Significance 1e-2 for the whole suite, Bonferroni-corrected over the configurations.
    const double alpha = 1e-2 / double(configs.size());
    uint64_t seed = 1234;
    int run = 0;
    for (const Config& c : configs) {
        ++seed; // each configuration keeps its own stream whichever family runs it
        bool selected = false;
        for (const char* p : prefixes) selected |= c.name.rfind(p, 0) == 0;
        if (!selected) continue;
        ++run;
        const Chi2Result r = runChi2(c, seed);
        INFO(c.name << ": p = " << r.pValue << ", dof = " << r.dof << ", continuous mass = " << r.continuousMass
                    << "; weight/pdf mismatches " << r.weightMismatches << " " << r.worstWeight);
        CHECK(r.pValue > alpha);
        CHECK(r.weightMismatches == 0);
        CHECK(r.continuousMass <= 1 + 1e-3);
    }
    CHECK(run > 0);
}

} // namespace

TEST_CASE("chi-square: diffuse, twosided and plastic sampling match pdf", "[bsdf][chi2]") {
    runFamily({"diffuse", "twosided", "plastic"});
}

TEST_CASE("chi-square: roughconductor sampling matches pdf", "[bsdf][chi2]") { runFamily({"roughconductor"}); }

TEST_CASE("chi-square: roughdielectric (Beckmann) sampling matches pdf", "[bsdf][chi2][long]") {
    runFamily({"roughdielectric beckmann"});
}

TEST_CASE("chi-square: roughdielectric (GGX, anisotropic, extreme eta) sampling matches pdf", "[bsdf][chi2]") {
    runFamily({"roughdielectric ggx", "roughdielectric aniso"});
}

TEST_CASE("chi-square: roughplastic sampling matches pdf", "[bsdf][chi2]") { runFamily({"roughplastic"}); }

TEST_CASE("chi-square: phong, ward, blendbsdf, mask and bumpmap sampling match pdf", "[bsdf][chi2]") {
    runFamily({"phong", "ward", "blendbsdf", "mask", "bumpmap"});
}

TEST_CASE("chi-square p-value helper matches known quantiles", "[bsdf]") {
    // Table values: the 0.95 quantile of chi2 with 1 dof is 3.841459, with 10 dof 18.307038, with 100
    // dof 124.342113.
    CHECK(gammaQ(0.5, 3.841459 / 2) == Approx(0.05).epsilon(1e-5));
    CHECK(gammaQ(5, 18.307038 / 2) == Approx(0.05).epsilon(1e-5));
    CHECK(gammaQ(50, 124.342113 / 2) == Approx(0.05).epsilon(1e-5));
}
