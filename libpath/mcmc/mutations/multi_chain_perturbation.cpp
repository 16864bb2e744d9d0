#include "mcmc/mutations/multi_chain_perturbation.h"

#include "mcmc/mutations/trace.h"

namespace lt {

MultiChainPerturbation::MultiChainPerturbation(const Scene& scene)
    : scene_(scene), sensor_(scene.camera),
      radius_(rasterRadii(scene.camera)), angle_{1e-4 * Pi / 180, 0.1 * Pi / 180} {}

std::vector<int> MultiChainPerturbation::stops(const MarkovPath& path) {
    const auto& v = path.v;
    std::vector<int> out{firstNonSpecularFromEye(v)};
    // At least two chains: x_{j-1} specular (otherwise it is the lens perturbation's path).
    if (out[0] < 1 || !isSpecular(v[size_t(out[0]) - 1])) return {};
    for (;;) {
        int c = out.back() - 1;
        while (c > 0 && isSpecular(v[size_t(c)]))
            --c;
        if (c == 0) return {}; // the chain runs into the light: no pair of adjacent non-specular vertices
        out.push_back(c);
        const PathVertex& partner = v[size_t(c) - 1];
        if (!isSpecular(partner)) return partner.isConnectible() ? out : std::vector<int>{};
    }
}

bool MultiChainPerturbation::suitable(const MarkovPath& x) const { return !stops(x).empty(); }

double MultiChainPerturbation::density(const MarkovPath& path, double pOffset,
                                       const std::vector<double>& thetas) const {
    const auto& v = path.v;
    const auto d = stops(path);
    if (d.empty()) return 0;
    double p = pOffset * eyeChainDensity(scene_, sensor_, v, d[0]);
    for (size_t s = 0; s + 1 < d.size() && p > 0; ++s) {
        const size_t from = size_t(d[s]);
        p *= v[from].convertDensity(angle_.sphereDensity(thetas[s]), v[from - 1]);
        for (int i = d[s] - 2; i >= d[s + 1] && p > 0; --i)
            p *= fixedLobeDensityFromEye(scene_, sensor_, v, size_t(i));
    }
    return p;
}

void MultiChainPerturbation::propose(const MarkovPath& x, Pcg32& rng, Proposal& out) const {
    out.reset();
    const auto d = stops(x);
    // 1. The lens perturbation through the first chain.
    double sampled = 1;
    const auto pOffset = perturbLensChain(scene_, sensor_, radius_, x, d[0], rng, out, sampled);
    if (!pOffset) return;
    // 2. At each further non-specular vertex, the old direction turned, through the next chain (step 2).
    std::vector<double> thetas;
    for (size_t s = 0; s + 1 < d.size(); ++s) {
        const size_t from = size_t(d[s]);
        const double theta = angle_.sample(rng.nextDouble());
        const double phi = 2 * Pi * rng.nextDouble();
        thetas.push_back(theta);
        const Vec3 dir = rotateDirection(x.v[from].directionTo(x.v[from - 1]), theta, phi);
        if (const auto why = followChain(scene_, x.v, out.y.v, d[s], d[s + 1], rayFrom(out.y.v[from], dir),
                                         angle_.sphereDensity(theta), Transport::Radiance, sampled)) {
            out.failed = why;
            return;
        }
    }
    // 3. Connect x_c' to x_{c-1}: evaluatePath.
    if (!evaluateProposal(scene_, x, out)) return;
    // 4. Q both ways: the same offsets, each path's own Jacobians (step 4).
    setTransitionDensities(out, x, sampled, density(out.y, *pOffset, thetas), density(x, *pOffset, thetas));
}

// It moves only paths through specular chains (Veach and Guibas 1997): without one in the scene it could never
// propose anything.
const MutationKind MultiChainPerturbation::Kind{
    "multi-chain",
    "perturbation",
    "the lens perturbation carried through D S+ D S* E paths, chain after chain",
    {},
    [](const MutationContext& c, const OptionValues&) -> std::unique_ptr<Mutation> {
        return std::make_unique<MultiChainPerturbation>(c.scene);
    },
    [](const SceneFeatures& f) { return f.specularChains ? std::string() : f.specularReason; },
    {},
    {}};

} // namespace lt
