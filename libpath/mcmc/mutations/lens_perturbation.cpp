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
    out = Proposal{};
    const int k = x.edges();
    const int j = firstNonSpecularFromEye(x.v);
    // 1. The raster offset (ALGORITHMS.md 2.2 step 2); off the sensor window is off the image.
    const auto cam = perturbCamera(scene_.camera, sensor_, radius_, x.raster, rng);
    if (!cam) {
        out.failed = RejectCause::LeftImage;
        return;
    }
    // 2. The camera ray through the chain to x_j' (step 3).
    out.y = x;
    double sampled = 1;
    if (const auto why = followChain(scene_, x.v, out.y.v, k, j, cam->ray, cam->pdfDir, Transport::Radiance, sampled)) {
        out.failed = why;
        return;
    }
    // 3. Connect x_j' to x_{j-1} (step 4): evaluatePath checks visibility and recomputes f and the raster.
    if (!evaluateProposal(scene_, out)) return;
    // 4. Q in both directions from the two paths; p_offset(r) is the same both ways.
    setTransitionDensities(out, x, sampled, cam->pOffset * eyeChainDensity(scene_, sensor_, out.y.v, j),
                           cam->pOffset * eyeChainDensity(scene_, sensor_, x.v, j));
}

} // namespace lt
