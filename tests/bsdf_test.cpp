// Unit and statistical tests of the BSDF layer (the chi-square sampling tests are in
// bsdf_chi2_test.cpp): half vectors, Fresnel, microfacet normalization, presets, reciprocity and the
// adjoint relation, energy bounds, delta-lobe consistency, the shading-normal adapter, and a NaN/Inf
// sweep over the stiff parameter ranges (roughness 1e-4 to 1, index of refraction 1.0001 to 4, grazing
// angles to 90 degrees).
#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "bsdf/blend.h"
#include "bsdf/bump_mapped.h"
#include "bsdf/conductor.h"
#include "bsdf/conductor_presets.h"
#include "bsdf/dielectric.h"
#include "bsdf/diffuse.h"
#include "bsdf/fresnel.h"
#include "bsdf/half_vector.h"
#include "bsdf/ior_presets.h"
#include "bsdf/mask.h"
#include "bsdf/microfacet.h"
#include "bsdf/phong.h"
#include "bsdf/plastic.h"
#include "bsdf/roughconductor.h"
#include "bsdf/roughdielectric.h"
#include "bsdf/roughplastic.h"
#include "bsdf/shading_correction.h"
#include "bsdf/thindielectric.h"
#include "bsdf/twosided.h"
#include "bsdf/ward.h"
#include "math/constants.h"
#include "util/error.h"
#include "math/frame.h"
#include "math/rng.h"
#include "math/warp.h"

using namespace lt;

namespace {

const Vec2 UV(0.5, 0.5);

std::shared_ptr<ConstantTexture> tex(double v) { return std::make_shared<ConstantTexture>(Spectrum(v)); }

Vec3 dirFromAngles(double thetaDeg, double phiDeg, bool below = false) {
    const double t = degToRad(thetaDeg), p = degToRad(phiDeg);
    return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), below ? -std::cos(t) : std::cos(t)};
}

// One-sided standard-normal quantile for a Bonferroni-corrected level: z with P(Z > z) = level, found
// by bisection on erfc (0.5 erfc(z / sqrt 2) = level).
double normalQuantile(double level) {
    double lo = 0, hi = 40;
    for (int i = 0; i < 200; ++i) {
        const double mid = 0.5 * (lo + hi);
        (0.5 * std::erfc(mid / std::sqrt(2.0)) > level ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

struct Named {
    std::string name;
    std::shared_ptr<const Bsdf> bsdf;
};

// Every BSDF kind, with a few parameter choices each.
struct Blend {
    std::string name;
    BlendParams params;
};

// Mixtures of a glossy with a diffuse lobe, of a delta with a glossy one, and of two refracting BSDFs
// with the same interface.
std::vector<Blend> blends() {
    RoughConductorParams rc;
    rc.alphaU = rc.alphaV = 0.1;
    RoughPlasticParams rp;
    rp.alpha = 0.2;
    RoughDielectricParams rd;
    rd.alphaU = rd.alphaV = 0.3;
    return {{"blendbsdf(diffuse, roughconductor)",
             {tex(0.3), std::make_shared<Diffuse>(DiffuseParams{tex(0.8)}), std::make_shared<RoughConductor>(rc)}},
            {"blendbsdf(conductor, roughplastic)",
             {tex(0.6), std::make_shared<Conductor>(ConductorParams{}), std::make_shared<RoughPlastic>(rp)}},
            {"blendbsdf(dielectric, roughdielectric)",
             {tex(0.5), std::make_shared<Dielectric>(DielectricParams{}), std::make_shared<RoughDielectric>(rd)}}};
}

// Cut-outs over a two-sided diffuse surface and over a rough conductor. (Grey opacities: the energy test
// bounds the largest channel of each sample's weight, which a colour opposite the nested BSDF's would
// break without breaking energy conservation per channel.)
std::vector<std::pair<std::string, MaskParams>> masks() {
    RoughConductorParams rc;
    rc.alphaU = rc.alphaV = 0.2;
    return {{"mask(twosided(diffuse))",
             {tex(0.3),
              std::make_shared<TwoSided>(TwoSidedParams{std::make_shared<Diffuse>(DiffuseParams{tex(0.8)}), nullptr})}},
            {"mask(roughconductor)", {tex(0.6), std::make_shared<RoughConductor>(rc)}}};
}

std::vector<Named> allBsdfs() {
    std::vector<Named> v;
    v.push_back({"diffuse", std::make_shared<Diffuse>(DiffuseParams{tex(0.8)})});
    v.push_back({"twosided(diffuse)", std::make_shared<TwoSided>(TwoSidedParams{
                                          std::make_shared<Diffuse>(DiffuseParams{tex(0.8)}), nullptr})});
    v.push_back({"dielectric", std::make_shared<Dielectric>(DielectricParams{})});
    v.push_back({"thindielectric", std::make_shared<ThinDielectric>(DielectricParams{})});
    v.push_back({"conductor", std::make_shared<Conductor>(ConductorParams{})});
    for (MicrofacetType t : {MicrofacetType::Beckmann, MicrofacetType::GGX})
        for (double a : {1e-3, 0.1, 0.6}) {
            const std::string suffix = std::string(t == MicrofacetType::GGX ? " ggx" : " beckmann") + " a=" +
                                       std::to_string(a);
            RoughConductorParams rc;
            rc.distribution = t;
            rc.alphaU = a;
            rc.alphaV = 2 * a;
            v.push_back({"roughconductor" + suffix, std::make_shared<RoughConductor>(rc)});
            RoughDielectricParams rd;
            rd.distribution = t;
            rd.alphaU = rd.alphaV = a;
            v.push_back({"roughdielectric" + suffix, std::make_shared<RoughDielectric>(rd)});
            RoughPlasticParams rp;
            rp.distribution = t;
            rp.alpha = a;
            v.push_back({"roughplastic" + suffix, std::make_shared<RoughPlastic>(rp)});
        }
    v.push_back({"plastic", std::make_shared<Plastic>(PlasticParams{})});
    PlasticParams nl;
    nl.nonlinear = true;
    v.push_back({"plastic nonlinear", std::make_shared<Plastic>(nl)});
    for (double n : {1.0, 30.0, 2000.0}) {
        PhongParams p;
        p.exponent = tex(n);
        p.reflectances.specularReflectance = tex(0.4);
        v.push_back({"phong n=" + std::to_string(n), std::make_shared<Phong>(p)});
    }
    for (WardVariant variant : {WardVariant::Ward, WardVariant::WardDuer, WardVariant::Balanced}) {
        WardParams p;
        p.variant = variant;
        p.alphaU = tex(0.05);
        p.alphaV = tex(0.3);
        v.push_back({"ward variant " + std::to_string(int(variant)), std::make_shared<Ward>(p)});
    }
    for (const Blend& b : blends())
        v.push_back({b.name, std::make_shared<BlendBsdf>(b.params)});
    for (const auto& [name, params] : masks())
        v.push_back({name, std::make_shared<MaskBsdf>(params)});
    // The bumpmap is the nested BSDF in a tilted frame (applied by the surface, scene/bump_frame.h): its local
    // functions are the nested ones, checked here like any BSDF all the same.
    v.push_back({"bumpmap(roughplastic)",
                 std::make_shared<BumpMappedBsdf>(tex(0.1), std::make_shared<RoughPlastic>(RoughPlasticParams{}))});
    return v;
}

} // namespace

TEST_CASE("generalized half vector and its Jacobian", "[bsdf]") {
    const Vec3 wi = dirFromAngles(40, 10);
    SECTION("reflection: h bisects, Jacobian 1/(4 |h.o|)") {
        const Vec3 wo = dirFromAngles(25, 200);
        const Vec3 h = *halfVector(wi, wo, 1);
        CHECK(dot(h, wi) == Approx(dot(h, wo)).epsilon(1e-12));
        CHECK(halfVectorJacobian(h, wi, wo, 1) == Approx(1 / (4 * std::abs(dot(h, wo)))).epsilon(1e-12));
    }
    SECTION("refraction: refract() output gives back the normal, Snell holds") {
        const double eta = 1.5; // entering the denser side
        const Vec3 m = normalize(Vec3(0.2, -0.1, 1));
        const Vec3 wo = *refract(wi, m, eta);
        const Vec3 h = *halfVector(wi, wo, eta);
        CHECK(length(h - m) < 1e-12);
        CHECK(length(cross(wi, m)) == Approx(eta * length(cross(wo, m))).epsilon(1e-12));
        CHECK(!refract(dirFromAngles(80, 0), Vec3(0, 0, 1), 1 / 1.5)); // into a less dense side: TIR
    }
    SECTION("Jacobian equals the solid-angle ratio measured by finite differences") {
        // Map a small triangle of wo directions to h and compare the areas (both on the unit sphere).
        for (double eta : {1.0, 1.5, 1 / 1.5}) {
            const Vec3 wo = eta == 1 ? dirFromAngles(30, 150) : dirFromAngles(20, 150, true);
            if (eta != 1 && !halfVector(wi, wo, eta)) continue;
            const Frame f = Frame::fromNormal(wo);
            const double eps = 1e-5;
            const Vec3 o1 = normalize(wo + eps * f.s), o2 = normalize(wo + eps * f.t);
            const Vec3 h0 = *halfVector(wi, wo, eta), h1 = *halfVector(wi, o1, eta), h2 = *halfVector(wi, o2, eta);
            const double areaO = length(cross(o1 - wo, o2 - wo)), areaH = length(cross(h1 - h0, h2 - h0));
            INFO("eta " << eta);
            // First-order finite differences: relative error O(eps) ~ 1e-5.
            CHECK(areaH / areaO == Approx(halfVectorJacobian(h0, wi, wo, eta)).epsilon(1e-4));
        }
    }
    SECTION("guards: index-matched straight-through and zero denominators give nothing or 0") {
        CHECK(!halfVector(wi, -wi, 1));
        CHECK(halfVectorJacobian(Vec3(1, 0, 0), Vec3(0, 0, 1), Vec3(0, 0, 1), 1) == 0);
        CHECK(length(halfVectorUnnormalized(wi, -wi, 1)) == 0);
    }
}

TEST_CASE("Fresnel: dielectric and conductor against closed forms", "[bsdf]") {
    for (double eta : {1.0001, 1.33, 1.5, 2.4, 4.0}) {
        const double r0 = sqr((eta - 1) / (eta + 1));
        double cosT;
        CHECK(fresnelDielectric(1.0, eta, cosT) == Approx(r0).epsilon(1e-12));
        CHECK(cosT == Approx(-1.0));
        CHECK(fresnelDielectric(-1.0, eta) == Approx(r0).epsilon(1e-12)); // same from inside
        // Total internal reflection beyond the critical angle from inside.
        const double cosCrit = std::sqrt(1 - 1 / (eta * eta));
        CHECK(fresnelDielectric(-0.5 * cosCrit, eta, cosT) == 1);
        CHECK(cosT == 0);
        // Reciprocity of the interface: F is the same for the two directions of one refraction.
        const double ci = 0.37;
        const double F = fresnelDielectric(ci, eta, cosT);
        CHECK(fresnelDielectric(cosT, eta) == Approx(F).epsilon(1e-10));
        // The diffuse Fresnel identity 1 - Fdr(1/eta) = (1 - Fdr(eta)) / eta^2 (plastic's energy balance).
        CHECK(1 - fresnelDiffuseReflectance(1 / eta) ==
              Approx((1 - fresnelDiffuseReflectance(eta)) / (eta * eta)).epsilon(1e-7));
    }
    CHECK(fresnelDielectric(0.3, 1.0) == 0);
    // Conductor at normal incidence: ((n-1)^2 + k^2) / ((n+1)^2 + k^2).
    const Spectrum eta(0.2, 1.1, 2.5), k(3.9, 2.4, 0.0);
    const Spectrum F = fresnelConductor(1.0, eta, k);
    for (int c = 0; c < 3; ++c)
        CHECK(F[c] == Approx((sqr(eta[c] - 1) + sqr(k[c])) / (sqr(eta[c] + 1) + sqr(k[c]))).epsilon(1e-12));
    // k = 0 reduces to the dielectric formula.
    CHECK(fresnelConductor(0.3, Spectrum(1.7), Spectrum(0.0)).r == Approx(fresnelDielectric(0.3, 1.7)).epsilon(1e-10));
    // "none" is a perfect mirror at every angle, including normal incidence (no 0/0).
    const auto none = *lookupConductor("none");
    for (double c : {0.0, 1e-9, 0.5, 1.0}) CHECK(fresnelConductor(c, none.eta, none.k).r == Approx(1.0));
}

TEST_CASE("conductor and IOR presets", "[bsdf]") {
    // Mitsuba's Cu in RGB mode as used by the veach-mis scene.
    const auto cu = lookupConductor("Cu");
    REQUIRE(cu);
    CHECK(cu->eta.r == Approx(0.200438).epsilon(1e-5));
    CHECK(cu->eta.g == Approx(0.924033).epsilon(1e-5));
    CHECK(cu->eta.b == Approx(1.10221).epsilon(1e-5));
    CHECK(cu->k.r == Approx(3.91295).epsilon(1e-5));
    CHECK(cu->k.g == Approx(2.45285).epsilon(1e-5));
    CHECK(cu->k.b == Approx(2.14219).epsilon(1e-5));
    for (const char* name : {"a-C", "Ag", "Al", "AlAs", "Au", "Be", "Cr", "Cs", "Cu", "Cu2O", "CuO", "d-C", "Hg",
                             "HgTe", "Ir", "K", "Li", "MgO", "Mo", "Na_palik", "Nb", "Ni_palik", "Rh", "Se", "SiC",
                             "SnTe", "Ta", "Te", "ThF4", "TiC", "TiN", "TiO2", "VC", "V_palik", "VN", "W", "none"}) {
        INFO(name);
        const auto p = lookupConductor(name);
        if (std::string(name) == "Cs") {
            // Mitsuba ships CsI (caesium iodide), not Cs; the brief's "Cs" has no Mitsuba data.
            CHECK(lookupConductor("CsI"));
            continue;
        }
        REQUIRE(p);
        for (int c = 0; c < 3; ++c) CHECK((p->eta[c] >= 0 && p->k[c] >= 0));
    }
    CHECK(!lookupConductor("Unobtainium"));
    CHECK(conductorPresetNames().size() >= 37);
    CHECK(*lookupIor("bk7") == 1.5046);
    CHECK(*lookupIor("Air") == 1.000277);
    CHECK(*lookupIor("water") == 1.3330);
    CHECK(*lookupIor("diamond") == 2.419);
    CHECK(!lookupIor("mithril"));
    CHECK_THROWS(checkIorPair("dielectric", -1, 1));
}

TEST_CASE("microfacet distributions are normalized", "[bsdf]") {
    // int D(m) (m.n) d omega = 1 and int D_v(m) d omega = 1, integrated in slope space
    // (d omega = cos^3 dA(slope)) with slopes scaled by alpha, polar, r = t / (1 - t) on a fine
    // midpoint grid; error of this quadrature is below 1e-3 for these smooth integrands.
    for (MicrofacetType type : {MicrofacetType::Beckmann, MicrofacetType::GGX})
        for (double a : {1e-3, 0.1, 0.7}) {
            const MicrofacetDistribution d(type, a, 1.7 * a);
            const Vec3 v = dirFromAngles(75, 30);
            double sumD = 0, sumV = 0;
            const int n = 800, m = 256;
            for (int i = 0; i < n; ++i)
                for (int j = 0; j < m; ++j) {
                    const double t = (i + 0.5) / n, phi = TwoPi * (j + 0.5) / m;
                    const double r = t / (1 - t), drdt = 1 / sqr(1 - t);
                    const Vec3 h = normalize(Vec3(a * r * std::cos(phi), 1.7 * a * r * std::sin(phi), 1));
                    const double w = h.z * h.z * h.z * a * 1.7 * a * r * drdt * (1.0 / n) * (TwoPi / m);
                    sumD += d.D(h) * h.z * w;
                    sumV += d.pdfVisible(v, h) * w;
                }
            INFO((type == MicrofacetType::GGX ? "ggx" : "beckmann") << " alpha " << a);
            CHECK(sumD == Approx(1).epsilon(2e-3));
            CHECK(sumV == Approx(1).epsilon(2e-3));
        }
}

TEST_CASE("reciprocity and the adjoint relation for refraction", "[bsdf]") {
    Pcg32 rng(42, 1);
    for (const Named& n : allBsdfs()) {
        if (!n.bsdf->hasGlossy() && !n.bsdf->hasDiffuse()) continue;
        INFO(n.name);
        const std::optional<InterfaceEta> eta = n.bsdf->eta();
        for (int k = 0; k < 200; ++k) {
            const Vec3 wi = warp::squareToUniformSphere({rng.nextDouble(), rng.nextDouble()});
            const Vec3 wo = warp::squareToUniformSphere({rng.nextDouble(), rng.nextDouble()});
            const Spectrum fr = n.bsdf->eval(wi, wo, UV, Transport::Radiance);
            const Spectrum fi = n.bsdf->eval(wi, wo, UV, Transport::Importance);
            const Spectrum frT = n.bsdf->eval(wo, wi, UV, Transport::Radiance);
            const Spectrum fiT = n.bsdf->eval(wo, wi, UV, Transport::Importance);
            const double tol = 1e-9 * std::max({1.0, fr.maxValue(), fi.maxValue(), frT.maxValue(), fiT.maxValue()});
            if (sameHemisphere(wi, wo)) {
                // Reflection is symmetric and mode independent.
                CHECK(std::abs(fr.r - frT.r) <= tol);
                CHECK(std::abs(fr.g - fi.g) <= tol);
            } else if (eta) {
                // f_Radiance(wi, wo) = f_Importance(wo, wi) (the adjoint BSDF, Veach thesis 5.2), and
                // generalized reciprocity f_I(wi, wo) / eta_wo^2 = f_I(wo, wi) / eta_wi^2.
                const double etaWi = wi.z > 0 ? eta->exterior : eta->interior;
                const double etaWo = wo.z > 0 ? eta->exterior : eta->interior;
                CHECK(std::abs(fr.r - fiT.r) <= tol);
                CHECK(std::abs(fi.r / (etaWo * etaWo) - fiT.r / (etaWi * etaWi)) <= tol);
            }
        }
    }
}

TEST_CASE("energy: directional albedo is at most one", "[bsdf]") {
    // Albedo = E[sample weight] (delta lobes included) with its standard error; the bound is
    // 1 + z stderr with z the normal quantile at level 1e-2 Bonferroni-corrected over all checks.
    const std::vector<Named> bsdfs = allBsdfs();
    const double thetas[] = {0, 30, 60, 80, 89};
    const int checks = int(bsdfs.size()) * 5 * 2;
    const double z = normalQuantile(1e-2 / checks);
    const int N = 20000;
    Pcg32 rng(7, 3);
    for (const Named& n : bsdfs)
        for (double th : thetas)
            for (bool below : {false, true}) {
                // Radiance-mode refraction carries (eta_wi/eta_wo)^2 > 1 when leaving the dense side, so
                // energy is bounded in Importance mode (bsdf.h).
                const Vec3 wi = dirFromAngles(th, 25, below);
                double sum = 0, sum2 = 0;
                for (int i = 0; i < N; ++i) {
                    const auto s = n.bsdf->sample(wi, UV, Transport::Importance, rng.nextDouble(),
                                                  {rng.nextDouble(), rng.nextDouble()});
                    const double w = s ? s->weight.maxValue() : 0;
                    sum += w;
                    sum2 += w * w;
                }
                const double mean = sum / N, se = std::sqrt(std::max(0.0, sum2 / N - mean * mean) / N);
                INFO(n.name << " theta " << th << (below ? " below" : "") << ": albedo " << mean << " +- " << se);
                CHECK(mean <= 1 + z * se + 1e-12);
            }
}

TEST_CASE("energy: analytic balances", "[bsdf]") {
    SECTION("smooth dielectric: R + T = 1 in Importance mode, T carries 1/eta^2 in Radiance mode") {
        for (double ior : {1.0001, 1.5, 4.0}) {
            DielectricParams p;
            p.intIOR = ior;
            p.extIOR = 1;
            const Dielectric d(p);
            for (bool below : {false, true})
                for (double th : {0.0, 30.0, 60.0, 89.9}) {
                    const Vec3 wi = dirFromAngles(th, 10, below);
                    const double etaRel = below ? 1 / ior : ior; // eta_wo / eta_wi of the refraction
                    double total = 0, totalRad = 0;
                    const Vec3 wr(-wi.x, -wi.y, wi.z);
                    if (const auto r = d.deltaEval(wi, wr, UV, Transport::Importance)) {
                        total += r->pdf * r->weight.r;
                        totalRad += r->pdf * d.deltaEval(wi, wr, UV, Transport::Radiance)->weight.r;
                    }
                    if (const auto wt = refract(wi, Vec3(0, 0, 1), etaRel)) {
                        const auto t = d.deltaEval(wi, *wt, UV, Transport::Importance);
                        const auto tr = d.deltaEval(wi, *wt, UV, Transport::Radiance);
                        REQUIRE(t);
                        REQUIRE(tr);
                        CHECK(t->eta == Approx(etaRel).epsilon(1e-15));
                        total += t->pdf * t->weight.r;
                        totalRad += tr->pdf * tr->weight.r * etaRel * etaRel;
                    }
                    INFO("ior " << ior << " theta " << th << (below ? " inside" : ""));
                    CHECK(total == Approx(1).epsilon(1e-12));
                    CHECK(totalRad == Approx(1).epsilon(1e-12));
                }
        }
    }
    SECTION("thin dielectric: R + T = 1") {
        const ThinDielectric t(DielectricParams{});
        for (double th : {0.0, 45.0, 89.9}) {
            const Vec3 wi = dirFromAngles(th, 0);
            const auto r = t.sample(wi, UV, Transport::Radiance, 0, {});
            const auto tr = t.sample(wi, UV, Transport::Radiance, 1 - 1e-16, {});
            REQUIRE(r);
            REQUIRE(tr);
            CHECK(r->pdf * r->weight.r + tr->pdf * tr->weight.r == Approx(1).epsilon(1e-12));
            CHECK(length(tr->wo + wi) < 1e-15);
        }
    }
    SECTION("white plastic conserves energy exactly (linear model); white rough plastic within its table error") {
        PlasticParams p;
        p.diffuseReflectance = tex(1.0);
        std::vector<Named> white = {{"plastic", std::make_shared<Plastic>(p)}};
        for (MicrofacetType t : {MicrofacetType::Beckmann, MicrofacetType::GGX})
            for (double a : {1e-3, 0.3, 1.0}) {
                RoughPlasticParams rp;
                rp.distribution = t;
                rp.alpha = a;
                rp.diffuseReflectance = tex(1.0);
                white.push_back({"roughplastic", std::make_shared<RoughPlastic>(rp)});
            }
        const double z = normalQuantile(1e-2 / (3.0 * white.size()));
        Pcg32 rng(11, 5);
        for (const Named& n : white)
            for (double th : {0.0, 50.0, 85.0}) {
                const Vec3 wi = dirFromAngles(th, 0);
                const int N = 100000;
                double sum = 0, sum2 = 0;
                for (int i = 0; i < N; ++i) {
                    const auto s = n.bsdf->sample(wi, UV, Transport::Radiance, rng.nextDouble(),
                                                  {rng.nextDouble(), rng.nextDouble()});
                    const double w = s ? s->weight.r : 0;
                    sum += w;
                    sum2 += w * w;
                }
                const double mean = sum / N, se = std::sqrt(std::max(0.0, sum2 / N - mean * mean) / N);
                // Rough plastic: the coat table (roughplastic.h) is exact up to its quadrature and
                // interpolation error, which measured against a 512x512 rule stays below 7e-4 for
                // alpha 1e-3..1 and incidence up to 89 degrees; 1e-3 bounds it.
                const double model = n.name == "plastic" ? 1e-9 : 1e-3;
                INFO(n.name << " alpha " << n.bsdf->roughness(UV) << " theta " << th << ": albedo " << mean << " +- "
                            << se);
                CHECK(std::abs(mean - 1) <= z * se + model);
            }
    }
}

TEST_CASE("delta lobes: deltaEval agrees with sample, eval/pdf are zero", "[bsdf]") {
    std::vector<Named> deltas = {
        {"dielectric", std::make_shared<Dielectric>(DielectricParams{})},
        {"thindielectric", std::make_shared<ThinDielectric>(DielectricParams{})},
        {"conductor", std::make_shared<Conductor>(ConductorParams{})},
        {"plastic", std::make_shared<Plastic>(PlasticParams{})},
        {"twosided(conductor)",
         std::make_shared<TwoSided>(TwoSidedParams{std::make_shared<Conductor>(ConductorParams{}), nullptr})},
    };
    for (const Blend& b : blends())
        if (b.params.first->hasDelta() || b.params.second->hasDelta())
            deltas.push_back({b.name, std::make_shared<BlendBsdf>(b.params)});
    for (const auto& [name, params] : masks())
        deltas.push_back({name, std::make_shared<MaskBsdf>(params)});
    {
        // A mask keeps its nested BSDF's roughness (its see-through lobe is delta and marks its own vertices)
        // and is an index-matched interface; a nested BSDF that refracts is refused.
        const MaskBsdf m(masks()[1].second);
        CHECK(m.roughness(UV) == Approx(masks()[1].second.nested->roughness(UV)));
        REQUIRE(m.eta());
        CHECK(m.eta()->interior == m.eta()->exterior);
        CHECK_THROWS_AS(MaskBsdf(MaskParams{tex(0.5), std::make_shared<Dielectric>(DielectricParams{})}), Error);
        // A blend of a delta part and a glossy one takes the glossy part's roughness.
        const BlendBsdf b(blends()[1].params);
        CHECK(b.roughness(UV) == Approx(blends()[1].params.second->roughness(UV)));
    }
    {
        // The straight-through lobe carries 1 - alpha with probability 1 - lum(alpha).
        MaskParams coloured = masks()[1].second;
        coloured.opacity = std::make_shared<ConstantTexture>(Spectrum(0.9, 0.5, 0.1));
        const MaskBsdf m(coloured);
        const Vec3 wi = dirFromAngles(30, 40);
        const auto s = m.sample(wi, UV, Transport::Radiance, 0.99, {0.5, 0.5});
        REQUIRE(s);
        const double q = Spectrum(0.9, 0.5, 0.1).luminance();
        CHECK(length(s->wo + wi) < 1e-12);
        CHECK(s->pdf == Approx(1 - q));
        CHECK(s->weight.r == Approx(0.1 / (1 - q)));
        CHECK(s->weight.b == Approx(0.9 / (1 - q)));
        CHECK(s->lobe == (LobeDelta | LobeTransmission));
    }
    // Two mirrors blended: the one mirror direction carries both lobes, (1 - w) 1 + w F_Cu.
    ConductorParams mirror;
    mirror.eta = lookupConductor("none")->eta;
    mirror.k = lookupConductor("none")->k;
    const auto copper = std::make_shared<Conductor>(ConductorParams{});
    const BlendBsdf mirrors(BlendParams{tex(0.25), std::make_shared<Conductor>(mirror), copper});
    deltas.push_back({"blendbsdf(mirror, copper)", std::make_shared<BlendBsdf>(mirrors)});
    {
        const Vec3 wi = dirFromAngles(40, 10);
        const auto s = mirrors.sample(wi, UV, Transport::Radiance, 0.9, {0.5, 0.5});
        const auto c = copper->sample(wi, UV, Transport::Radiance, 0.5, {0.5, 0.5});
        REQUIRE(s);
        REQUIRE(c);
        CHECK(s->pdf == Approx(1));
        CHECK(s->weight.r == Approx(0.75 + 0.25 * c->weight.r).epsilon(1e-12));
        CHECK(s->weight.b == Approx(0.75 + 0.25 * c->weight.b).epsilon(1e-12));
    }
    Pcg32 rng(5, 9);
    for (const Named& n : deltas) {
        INFO(n.name);
        const bool onlyDelta = !n.bsdf->hasDiffuse() && !n.bsdf->hasGlossy();
        for (int k = 0; k < 500; ++k) {
            const Vec3 wi = warp::squareToUniformSphere({rng.nextDouble(), rng.nextDouble()});
            for (Transport mode : {Transport::Radiance, Transport::Importance}) {
                const auto s = n.bsdf->sample(wi, UV, mode, rng.nextDouble(), {rng.nextDouble(), rng.nextDouble()});
                if (onlyDelta) {
                    const Vec3 wo = warp::squareToUniformSphere({rng.nextDouble(), rng.nextDouble()});
                    CHECK(n.bsdf->eval(wi, wo, UV, mode).isBlack());
                    CHECK(n.bsdf->pdf(wi, wo, UV) == 0);
                }
                if (!s || !(s->lobe & LobeDelta)) continue;
                const auto d = n.bsdf->deltaEval(wi, s->wo, UV, mode);
                REQUIRE(d);
                CHECK(d->pdf == Approx(s->pdf).epsilon(1e-12));
                CHECK(d->weight.r == Approx(s->weight.r).epsilon(1e-12));
                CHECK(d->weight.b == Approx(s->weight.b).epsilon(1e-12));
                CHECK(d->lobe == s->lobe);
                CHECK(d->eta == s->eta);
                // A direction 10 tolerances away from the specular one is not specular.
                const Frame f = Frame::fromNormal(s->wo);
                CHECK(!n.bsdf->deltaEval(wi, normalize(s->wo + 10 * DeltaDirectionTolerance * f.s), UV, mode));
            }
        }
    }
    // Lobe choice frequency of the dielectric equals the Fresnel reflectance (binomial, 5 sigma).
    const Dielectric d(DielectricParams{});
    const Vec3 wi = dirFromAngles(70, 0);
    const double F = fresnelDielectric(wi.z, 1.5046 / 1.000277);
    int reflections = 0;
    const int N = 100000;
    for (int i = 0; i < N; ++i)
        if (d.sample(wi, UV, Transport::Radiance, rng.nextDouble(), {})->lobe & LobeReflection) ++reflections;
    CHECK(std::abs(reflections - N * F) <= 5 * std::sqrt(N * F * (1 - F)));
}

TEST_CASE("shading-normal adapter: light leaks and the adjoint correction", "[bsdf]") {
    const auto diffuse =
        std::make_shared<TwoSided>(TwoSidedParams{std::make_shared<Diffuse>(DiffuseParams{tex(0.5)}), nullptr});
    RoughDielectricParams rdp;
    rdp.alphaU = rdp.alphaV = 0.3;
    const auto glass = std::make_shared<RoughDielectric>(rdp);
    const Vec3 ng(0, 0, 1);
    const Vec3 ns = normalize(Vec3(0.3, 0, 1)); // shading normal tilted by ~17 degrees
    const Frame frame = Frame::fromNormal(ns);

    SECTION("identical normals: plain local evaluation in both modes") {
        const WorldBsdf w{*glass, Frame::fromNormal(ng), ng, UV};
        const Vec3 wi = dirFromAngles(30, 0), wo = dirFromAngles(40, 170, true);
        for (Transport m : {Transport::Radiance, Transport::Importance})
            CHECK(w.eval(wi, wo, m).r == Approx(glass->eval(wi, wo, UV, m).r).epsilon(1e-12));
    }
    SECTION("classification disagreement gives zero and sample rejects it") {
        const WorldBsdf w{*diffuse, frame, ng, UV};
        // Above the geometric plane but below the shading plane: reflection for ng, transmission for ns.
        const Vec3 wi = dirFromAngles(45, 0);
        const Vec3 wo = normalize(Vec3(-1, 0, 0.1));
        REQUIRE(dot(wo, ng) > 0);
        REQUIRE(dot(wo, ns) < 0);
        CHECK(w.eval(wi, wo, Transport::Radiance).isBlack());
        CHECK(w.eval(wi, wo, Transport::Importance).isBlack());
        Pcg32 rng(3, 3);
        for (int i = 0; i < 2000; ++i) {
            const auto s = w.sample(wi, Transport::Radiance, rng.nextDouble(), {rng.nextDouble(), rng.nextDouble()});
            if (s) CHECK(dot(s->wo, ng) * dot(wi, ng) > 0);
        }
    }
    SECTION("Importance / Radiance = |wi.ns||wo.ng| / (|wi.ng||wo.ns|) (Veach Eq. 5.21), samples consistent") {
        for (const Bsdf* b : {static_cast<const Bsdf*>(diffuse.get()), static_cast<const Bsdf*>(glass.get())}) {
            const WorldBsdf w{*b, frame, ng, UV};
            Pcg32 rng(8, 1);
            int tested = 0;
            for (int i = 0; i < 2000; ++i) {
                const Vec3 wi = warp::squareToUniformSphere({rng.nextDouble(), rng.nextDouble()});
                const Vec3 wo = warp::squareToUniformSphere({rng.nextDouble(), rng.nextDouble()});
                const Spectrum fr = w.eval(wi, wo, Transport::Radiance), fi = w.eval(wi, wo, Transport::Importance);
                if (!(fr.r > 1e-100)) continue; // denormal values carry no relative precision
                // Importance vs Radiance differ by the correction factor times the BSDF's own adjointness.
                const Spectrum localR = b->eval(frame.toLocal(wi), frame.toLocal(wo), UV, Transport::Radiance);
                const Spectrum localI = b->eval(frame.toLocal(wi), frame.toLocal(wo), UV, Transport::Importance);
                const double factor = std::abs(dot(wi, ns) * dot(wo, ng) / (dot(wi, ng) * dot(wo, ns)));
                CHECK(fi.r / fr.r == Approx(factor * localI.r / localR.r).epsilon(1e-9));
                // The effective BSDF times |wo.ng| is f_s |wo.ns| in Radiance mode.
                CHECK(fr.r * std::abs(dot(wo, ng)) == Approx(localR.r * std::abs(dot(wo, ns))).epsilon(1e-9));
                ++tested;
            }
            CHECK(tested > 100);
            // Sample weights equal eval * |wo.ng| / pdf in both modes.
            for (int i = 0; i < 2000; ++i) {
                const Vec3 wi = warp::squareToUniformSphere({rng.nextDouble(), rng.nextDouble()});
                for (Transport m : {Transport::Radiance, Transport::Importance}) {
                    const auto s = w.sample(wi, m, rng.nextDouble(), {rng.nextDouble(), rng.nextDouble()});
                    if (!s) continue;
                    const double expect = w.eval(wi, s->wo, m).r * std::abs(dot(s->wo, ng)) / w.pdf(wi, s->wo);
                    CHECK(s->weight.r == Approx(expect).epsilon(1e-6));
                }
            }
        }
    }
}

TEST_CASE("no NaN or Inf over the stiff parameter ranges", "[bsdf]") {
    std::vector<Named> bsdfs = allBsdfs();
    for (double a : {1e-4, 1e-2, 1.0})
        for (double ior : {1.0001, 1.01, 2.0, 4.0})
            for (MicrofacetType t : {MicrofacetType::Beckmann, MicrofacetType::GGX}) {
                RoughDielectricParams rd;
                rd.distribution = t;
                rd.alphaU = a;
                rd.alphaV = a * 0.5 + 1e-4;
                rd.intIOR = ior;
                rd.extIOR = 1;
                bsdfs.push_back({"roughdielectric", std::make_shared<RoughDielectric>(rd)});
                RoughConductorParams rc;
                rc.distribution = t;
                rc.alphaU = rc.alphaV = a;
                rc.eta = Spectrum(ior);
                rc.k = Spectrum(ior - 1);
                bsdfs.push_back({"roughconductor", std::make_shared<RoughConductor>(rc)});
                RoughPlasticParams rp;
                rp.distribution = t;
                rp.alpha = a;
                rp.intIOR = ior;
                bsdfs.push_back({"roughplastic", std::make_shared<RoughPlastic>(rp)});
            }
    for (double ior : {1.0001, 4.0}) {
        DielectricParams dp;
        dp.intIOR = ior;
        dp.extIOR = 1;
        bsdfs.push_back({"dielectric", std::make_shared<Dielectric>(dp)});
        PlasticParams pp;
        pp.intIOR = ior;
        pp.nonlinear = true;
        pp.diffuseReflectance = tex(1.0);
        bsdfs.push_back({"plastic", std::make_shared<Plastic>(pp)});
    }
    for (double a : {1e-4, 1e-2, 1.0}) {
        PhongParams pp;
        pp.exponent = tex(2 / (a * a) - 2); // the Beckmann-equivalent alpha a
        bsdfs.push_back({"phong", std::make_shared<Phong>(pp)});
        for (WardVariant variant : {WardVariant::Ward, WardVariant::WardDuer, WardVariant::Balanced}) {
            WardParams wp;
            wp.variant = variant;
            wp.alphaU = tex(a);
            wp.alphaV = tex(a * 0.5 + 1e-4);
            bsdfs.push_back({"ward", std::make_shared<Ward>(wp)});
        }
    }
    ConductorParams none;
    none.eta = lookupConductor("none")->eta;
    none.k = lookupConductor("none")->k;
    bsdfs.push_back({"conductor none", std::make_shared<Conductor>(none)});

    const auto finiteNonNegative = [](const Spectrum& s) {
        return s.isFinite() && s.r >= 0 && s.g >= 0 && s.b >= 0;
    };
    Pcg32 rng(99, 4);
    long failures = 0;
    for (const Named& n : bsdfs) {
        for (double th : {0.0, 1e-7, 30.0, 70.0, 85.0, 89.0, 89.9, 90.0})
            for (bool below : {false, true}) {
                const Vec3 wi = dirFromAngles(th, 33, below);
                std::vector<Vec3> wos = {Vec3(-wi.x, -wi.y, wi.z), -wi, Vec3(wi.x, wi.y, -wi.z), Vec3(0, 0, 1),
                                         Vec3(0, 0, -1), normalize(Vec3(1, 0, 0)), wi};
                for (int k = 0; k < 24; ++k)
                    wos.push_back(warp::squareToUniformSphere({rng.nextDouble(), rng.nextDouble()}));
                for (Transport m : {Transport::Radiance, Transport::Importance}) {
                    for (int k = 0; k < 64; ++k) {
                        // Include the corners of the unit square.
                        const double u0 = k == 0 ? 0.0 : (k == 1 ? 1 - 1e-16 : rng.nextDouble());
                        const Vec2 u = k < 2 ? Vec2(u0, u0) : Vec2(rng.nextDouble(), rng.nextDouble());
                        const auto s = n.bsdf->sample(wi, UV, m, rng.nextDouble(), u);
                        if (!s) continue;
                        wos.push_back(s->wo);
                        if (!finiteNonNegative(s->weight) || !std::isfinite(s->pdf) || !(s->pdf > 0) ||
                            !isFinite(s->wo) || std::abs(length(s->wo) - 1) > 1e-9) {
                            ++failures;
                            UNSCOPED_INFO(n.name << " sample theta " << th << " weight " << s->weight.r << " pdf "
                                                 << s->pdf);
                        }
                    }
                    for (const Vec3& wo : wos) {
                        const Spectrum f = n.bsdf->eval(wi, wo, UV, m);
                        const double p = n.bsdf->pdf(wi, wo, UV);
                        if (!finiteNonNegative(f) || !std::isfinite(p) || p < 0) {
                            ++failures;
                            UNSCOPED_INFO(n.name << " eval theta " << th << " f " << f.r << " pdf " << p);
                        }
                    }
                }
            }
    }
    CHECK(failures == 0);
}

TEST_CASE("twosided mirrors the back side onto the front, roughness and lobes are reported", "[bsdf]") {
    const auto front = std::make_shared<Diffuse>(DiffuseParams{tex(0.8)});
    const auto back = std::make_shared<Diffuse>(DiffuseParams{tex(0.2)});
    const TwoSided both(TwoSidedParams{front, back});
    const Vec3 wiBack = dirFromAngles(30, 0, true), woBack = dirFromAngles(50, 90, true);
    CHECK(both.eval(wiBack, woBack, UV, Transport::Radiance).r == Approx(0.2 * InvPi));
    CHECK(both.eval(dirFromAngles(30, 0), dirFromAngles(50, 90), UV, Transport::Radiance).r == Approx(0.8 * InvPi));
    CHECK(both.eval(wiBack, dirFromAngles(50, 90), UV, Transport::Radiance).isBlack()); // no transmission
    const auto s = both.sample(wiBack, UV, Transport::Radiance, 0.5, {0.3, 0.6});
    REQUIRE(s);
    CHECK(s->wo.z < 0);
    CHECK(s->weight.r == Approx(0.2));
    CHECK_THROWS_AS(TwoSided(TwoSidedParams{std::make_shared<Dielectric>(DielectricParams{}), nullptr}), Error);

    // Beckmann-equivalent roughness (bsdf.h): GGX alpha / sqrt(2), the sharper axis when anisotropic.
    RoughConductorParams rc;
    rc.distribution = MicrofacetType::GGX;
    rc.alphaU = 0.4;
    rc.alphaV = 0.2;
    CHECK(RoughConductor(rc).roughness(UV) == Approx(0.2 / std::sqrt(2.0)));
    CHECK(std::isinf(front->roughness(UV)));
    CHECK(Dielectric(DielectricParams{}).roughness(UV) == 0);
    CHECK(Dielectric(DielectricParams{}).eta()->interior == 1.5046);
    CHECK(!front->eta());
}

TEST_CASE("phong's exponent and ward's alphas read from textures at uv, as the constants there", "[bsdf]") {
    // A checkerboard: value 10 at uv (0.1, 0.1) (color0), 200 at (0.6, 0.1) (color1); scaled down for ward.
    const auto board = [](double a, double b) {
        return std::make_shared<CheckerboardTexture>(Spectrum(a), Spectrum(b), Vec2(0, 0), Vec2(1, 1));
    };
    PhongParams textured;
    textured.exponent = board(10, 200);
    WardParams texturedWard;
    texturedWard.alphaU = board(0.05, 0.4);
    texturedWard.alphaV = board(0.3, 0.02);
    for (const auto& [uv, n, au, av] :
         {std::tuple{Vec2(0.1, 0.1), 10.0, 0.05, 0.3}, std::tuple{Vec2(0.6, 0.1), 200.0, 0.4, 0.02}}) {
        PhongParams constant;
        constant.exponent = tex(n);
        WardParams constantWard;
        constantWard.alphaU = tex(au);
        constantWard.alphaV = tex(av);
        const std::pair<std::shared_ptr<const Bsdf>, std::shared_ptr<const Bsdf>> pairs[] = {
            {std::make_shared<Phong>(textured), std::make_shared<Phong>(constant)},
            {std::make_shared<Ward>(texturedWard), std::make_shared<Ward>(constantWard)}};
        for (const auto& [a, b] : pairs) {
            CAPTURE(a->typeName(), uv.x);
            CHECK(a->roughness(uv) == b->roughness(uv));
            const Vec3 wi = dirFromAngles(35, 20);
            for (int i = 0; i < 64; ++i) {
                const Vec2 u((i % 8 + 0.5) / 8, (i / 8 + 0.5) / 8);
                const auto sa = a->sample(wi, uv, Transport::Radiance, 0.3, u);
                const auto sb = b->sample(wi, uv, Transport::Radiance, 0.3, u);
                REQUIRE(bool(sa) == bool(sb));
                if (!sa) continue;
                CHECK(sa->wo == sb->wo);
                CHECK(sa->pdf == sb->pdf);
                CHECK(a->eval(wi, sa->wo, uv, Transport::Radiance) == b->eval(wi, sa->wo, uv, Transport::Radiance));
            }
        }
    }
    // The other square's exponent is another lobe: the texture is read, not its first value.
    CHECK(Phong(textured).roughness({0.1, 0.1}) != Phong(textured).roughness({0.6, 0.1}));
}
