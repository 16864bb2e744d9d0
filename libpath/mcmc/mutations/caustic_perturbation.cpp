#include "mcmc/mutations/caustic_perturbation.h"

#include "math/frame.h"
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
    // A light at infinity moves its ray sideways (a directional light's one direction included).
    const PathVertex& start = x.v[size_t(chainStart(x))];
    return start.infinite || start.isConnectible();
}

ReciprocalKernel CausticPerturbation::steps(const MarkovPath& path) const {
    const int k = path.edges();
    const auto& v = path.v;
    const int l = chainStart(path);
    const double dE = length(v[size_t(k)].si.p - v[size_t(k) - 1].si.p);
    if (v[size_t(l)].infinite) {
        // Offsets within the scene's disk.
        const double scale = radiansPerPixel_ * dE, R = scene_.sceneRadius();
        return {std::min(radius_.lo * scale, R), std::min(radius_.hi * scale, 2 * R)};
    }
    double dL = 0;
    for (int i = l; i < k - 1; ++i)
        dL += length(v[size_t(i) + 1].si.p - v[size_t(i)].si.p);
    const double scale = radiansPerPixel_ * dE / dL;
    // Never beyond the opposite direction.
    return {std::min(radius_.lo * scale, Pi / 2), std::min(radius_.hi * scale, Pi)};
}

double CausticPerturbation::stepDensity(const MarkovPath& path, double step) const {
    const ReciprocalKernel range = steps(path);
    return path.v[size_t(chainStart(path))].infinite ? range.planeDensity(step) : range.sphereDensity(step);
}

double CausticPerturbation::chainDensity(const MarkovPath& path, double pdfStep) const {
    const int k = path.edges();
    const int l = chainStart(path);
    double p = path.v[size_t(l)].convertDensity(pdfStep, path.v[size_t(l) + 1]);
    for (int i = l + 2; i < k && p > 0; ++i)
        p *= fixedLobeDensityFromLight(scene_, path.v, size_t(i));
    return p;
}

void CausticPerturbation::propose(const MarkovPath& x, Pcg32& rng, Proposal& out) const {
    out.reset();
    const int k = x.edges();
    const int l = chainStart(x);
    const PathVertex& start = x.v[size_t(l)];
    // 1. Turn the direction leaving x_l, or at infinity move the parallel ray sideways.
    const double step = steps(x).sample(rng.nextDouble());
    const double phi = 2 * Pi * rng.nextDouble();
    const Vec3 dir = start.directionTo(x.v[size_t(l) + 1]);
    Ray ray;
    if (start.infinite) {
        const Frame f = Frame::fromNormal(dir);
        const Vec3 through = x.v[size_t(l) + 1].p() + (f.s * std::cos(phi) + f.t * std::sin(phi)) * step;
        ray = Ray{scene_.sceneDisk().beyond(through, -dir), dir};
    } else {
        ray = rayFrom(start, rotateDirection(dir, step, phi));
    }
    const double pdfStep = stepDensity(x, step);
    // 2. Through the chain to x_{k-1}' (step 3), then to the camera: evaluatePath recomputes the raster.
    out.y = x;
    if (start.infinite) out.y.v[size_t(l)].si.p = ray.o; // where its ray now starts (path/vertex.h environmentVertex)
    double sampled = 1;
    if (const auto why = followChain(scene_, x.v, out.y.v, l, k - 1, ray, pdfStep, Transport::Importance, sampled)) {
        out.failed = why;
        return;
    }
    if (!evaluateProposal(scene_, x, out)) return;
    // 3. Q both ways; the reverse step of the same size has the density of y's range
    // (the kernel depends on the state, so the reverse density takes its parameters at y).
    setTransitionDensities(out, x, sampled, chainDensity(out.y, pdfStep), chainDensity(x, stepDensity(out.y, step)));
}

// It moves only paths through specular chains (Veach and Guibas 1997): without one in the scene it could never
// propose anything.
const MutationKind CausticPerturbation::Kind{
    "caustic",
    "perturbation",
    "turns the light end of (L|D) S+ D E paths (moves a sky's or sun's ray sideways): caustics on a diffuse surface "
    "seen directly",
    {},
    [](const MutationContext& c, const OptionValues&) -> std::unique_ptr<Mutation> {
        return std::make_unique<CausticPerturbation>(c.scene);
    },
    [](const SceneFeatures& f) { return f.specularChains ? std::string() : f.specularReason; },
    {},
    {}};

} // namespace lt
