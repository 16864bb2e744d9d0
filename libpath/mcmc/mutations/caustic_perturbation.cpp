#include "mcmc/mutations/caustic_perturbation.h"

#include "mcmc/mutations/trace.h"

namespace lt {

CausticPerturbation::CausticPerturbation(const Scene& scene)
    : scene_(scene), radiansPerPixel_(radiansPerPixel(scene.camera)), radius_(rasterRadii(scene.camera)) {}

int CausticPerturbation::chainStart(const MarkovPath& path) {
    int l = path.edges() - 2;
    while (l > 0 && isSpecular(path.v[size_t(l)]))
        --l;
    return l;
}

bool CausticPerturbation::suitable(const MarkovPath& x) const {
    const int k = x.edges();
    if (k < 3 || isSpecular(x.v[size_t(k) - 1]) || !isSpecular(x.v[size_t(k) - 2])) return false;
    // A directional light has no direction to turn.
    const PathVertex& start = x.v[size_t(chainStart(x))];
    return !start.infinite && start.isConnectible();
}

ReciprocalKernel CausticPerturbation::angles(const MarkovPath& path) const {
    const int k = path.edges();
    const auto& v = path.v;
    const double dE = length(v[size_t(k)].si.p - v[size_t(k) - 1].si.p);
    double dL = 0;
    for (int i = chainStart(path); i < k - 1; ++i)
        dL += length(v[size_t(i) + 1].si.p - v[size_t(i)].si.p);
    const double scale = radiansPerPixel_ * dE / dL;
    // Never beyond the opposite direction.
    return {std::min(radius_.lo * scale, Pi / 2), std::min(radius_.hi * scale, Pi)};
}

double CausticPerturbation::chainDensity(const MarkovPath& path, double pdfDir) const {
    const int k = path.edges();
    const int l = chainStart(path);
    double p = path.v[size_t(l)].convertDensity(pdfDir, path.v[size_t(l) + 1]);
    for (int i = l + 2; i < k && p > 0; ++i)
        p *= fixedLobeDensityFromLight(scene_, path.v, size_t(i));
    return p;
}

void CausticPerturbation::propose(const MarkovPath& x, Pcg32& rng, Proposal& out) const {
    out = Proposal{};
    const int k = x.edges();
    const int l = chainStart(x);
    const PathVertex& start = x.v[size_t(l)];
    // 1. Turn the direction leaving x_l.
    const ReciprocalKernel range = angles(x);
    const double theta = range.sample(rng.nextDouble());
    const double phi = 2 * Pi * rng.nextDouble();
    const Vec3 dir = rotateDirection(start.directionTo(x.v[size_t(l) + 1]), theta, phi);
    const double pdfDir = range.sphereDensity(theta);
    // 2. Through the chain to x_{k-1}' (step 3), then to the camera: evaluatePath recomputes the raster.
    out.y = x;
    double sampled = 1;
    if (const auto why =
            followChain(scene_, x.v, out.y.v, l, k - 1, rayFrom(start, dir), pdfDir, Transport::Importance, sampled)) {
        out.failed = why;
        return;
    }
    if (!evaluateProposal(scene_, x, out)) return;
    // 3. Q both ways; the reverse turn by the same theta has the density of y's range
    // (the kernel depends on the state, so the reverse density takes its parameters at y).
    setTransitionDensities(out, x, sampled, chainDensity(out.y, pdfDir),
                           chainDensity(x, angles(out.y).sphereDensity(theta)));
}

} // namespace lt
