#include "mcmc/mutations/lens_perturbation.h"

namespace lt {

LensPerturbation::LensPerturbation(const Scene& scene)
    : scene_(scene), sensor_(scene.camera), radius_(rasterRadii(scene.camera)) {}

bool LensPerturbation::suitable(const MarkovPath& x) const {
    // x_j non-specular behind the chain, and x_{j-1} (its connection partner) non-specular or the light.
    const int j = firstNonSpecularFromEye(x.v);
    if (j < 1) return false;
    const PathVertex& partner = x.v[size_t(j) - 1];
    return !isSpecular(partner) && partner.isConnectible();
}

void LensPerturbation::propose(const MarkovPath& x, Pcg32& rng, Proposal& out) const {
    out.reset();
    const int j = firstNonSpecularFromEye(x.v);
    // 1.-2. The raster offset and the camera ray through the chain to x_j'.
    double sampled = 1;
    const auto pOffset = perturbLensChain(scene_, sensor_, radius_, x, j, rng, out, sampled);
    if (!pOffset) return;
    // 3. Connect x_j' to x_{j-1} (step 4): evaluatePath checks visibility and recomputes f and the raster.
    if (!evaluateProposal(scene_, x, out)) return;
    // 4. Q in both directions from the two paths; p_offset(r) is the same both ways.
    setTransitionDensities(out, x, sampled, *pOffset * eyeChainDensity(scene_, sensor_, out.y.v, j),
                           *pOffset * eyeChainDensity(scene_, sensor_, x.v, j));
}

const MutationKind LensPerturbation::Kind{
    "lens",
    "perturbation",
    "moves the eye end of (L|D) D S* E paths to a nearby raster position",
    {},
    [](const MutationContext& c, const OptionValues&) -> std::unique_ptr<Mutation> {
        return std::make_unique<LensPerturbation>(c.scene);
    },
    [](const SceneFeatures&) { return std::string(); },
    {},
    {}};

} // namespace lt
