#include "mcmc/mutations/lens_subpath_mutation.h"

#include "bsdf/shading_correction.h"
#include "mcmc/mutations/specular_chain.h"
#include "mcmc/mutations/trace.h"

namespace lt {

namespace {

// The delta lobes of surface vertex v for the direction wEye toward the eye, in radiance transport: the
// reflection and the transmission one (either may be missing), with their probabilities in pdf.
struct DeltaLobes {
    std::optional<BsdfSample> reflection, transmission;

    DeltaLobes(const PathVertex& v, const Vec3& wEye)
        : reflection(deltaLobe(v, wEye, LobeReflection, Transport::Radiance)),
          transmission(deltaLobe(v, wEye, LobeTransmission, Transport::Radiance)) {}
    [[nodiscard]] double reflectionProbability() const { return reflection ? reflection->pdf : 0.0; }
    // The walk stops at v with the probability left to the non-delta lobes.
    [[nodiscard]] double stopProbability() const {
        return std::max(0.0, 1 - reflectionProbability() - (transmission ? transmission->pdf : 0.0));
    }
};

} // namespace

LensSubpathMutation::LensSubpathMutation(const Scene& scene, int maxEdges)
    : scene_(scene), maxEdges_(maxEdges), sensor_(scene.camera) {}

bool LensSubpathMutation::suitable(const MarkovPath& x) const {
    // As the lens perturbation: x_{j-1}, kept, must be a connection partner (non-specular or the light).
    const int j = firstNonSpecularFromEye(x.v);
    if (j < 1) return false;
    const PathVertex& partner = x.v[size_t(j) - 1];
    return !isSpecular(partner) && partner.isConnectible();
}

double LensSubpathMutation::subpathDensity(const std::vector<PathVertex>& v, int j) const {
    double p = DeltaLobes(v[size_t(j)], v[size_t(j)].directionTo(v[size_t(j) + 1])).stopProbability();
    for (size_t i = size_t(j); p > 0 && i + 1 < v.size(); ++i)
        p *= densityFromEye(scene_, sensor_, v, i);
    return p;
}

void LensSubpathMutation::propose(const MarkovPath& x, Pcg32& rng, Proposal& out) const {
    out.reset();
    const int j = firstNonSpecularFromEye(x.v);
    auto fail = [&](RejectCause why) { out.failed = why; };
    // 1. The new lens subpath, eye to light: a camera ray uniform over the sensor window, then at each hit
    // a delta lobe or the stop, each with its probability.
    std::vector<PathVertex> eye{x.v.back()};
    auto first = traceFromCamera(scene_, sensor_, eye.back(), rng);
    if (!first) return fail(RejectCause::ZeroContribution);
    double sampled = first->density;
    eye.push_back(std::move(first->v));
    for (;;) {
        // The kept vertices x_0 .. x_{j-1} and the new ones but the camera make the new path's edges.
        if (j + int(eye.size()) - 1 > maxEdges_) return fail(RejectCause::ZeroContribution);
        PathVertex& at = eye.back();
        if (at.type != VertexType::Surface || !at.bsdf) return fail(RejectCause::ZeroContribution);
        const Vec3 wEye = at.directionTo(eye[eye.size() - 2]);
        const DeltaLobes lobes(at, wEye);
        const double u = rng.nextDouble();
        if (u >= 1 - lobes.stopProbability()) {
            // 2. Stop: x_j', to be joined to x_{j-1} through its non-delta lobes.
            at.delta = false;
            at.lobe = at.bsdf->lobes() & ~LobeDelta;
            if (!at.isConnectible()) return fail(RejectCause::ZeroContribution);
            sampled *= lobes.stopProbability();
            break;
        }
        const BsdfSample& lobe = u < lobes.reflectionProbability() ? *lobes.reflection : *lobes.transmission;
        at.delta = true;
        at.lobe = lobe.lobe;
        auto next = traceVertex(scene_, rayFrom(at, lobe.wo));
        if (!next) return fail(RejectCause::ZeroContribution);
        const auto imp = at.worldBsdf().deltaEval(lobe.wo, wEye, Transport::Importance);
        if (!imp) return fail(RejectCause::ZeroContribution);
        sampled *= eyeSideDeltaDensity(*imp, lobe, geometryTerm(at, *next));
        eye.push_back(std::move(*next));
    }
    // 3. Join: the kept prefix, then the new subpath light to eye; evaluatePath checks the connection.
    out.y.v.assign(x.v.begin(), x.v.begin() + j);
    out.y.v.insert(out.y.v.end(), eye.rbegin(), eye.rend());
    if (!evaluateProposal(scene_, x, out)) return;
    // 4. T of each lens subpath from its path alone.
    setTransitionDensities(out, x, sampled, subpathDensity(out.y.v, j), subpathDensity(x.v, j));
}

const MutationKind LensSubpathMutation::Kind{
    "lens-subpath",
    "mutation",
    "a fresh eye end of (L|D) D S* E paths through a random raster position",
    {},
    [](const MutationContext& c, const OptionValues&) -> std::unique_ptr<Mutation> {
        return std::make_unique<LensSubpathMutation>(c.scene, c.maxEdges);
    },
    [](const SceneFeatures&) {
        return std::string(
            "optional (Veach 1997; Mitsuba dropped it for want of a gain); ask for it with --strategies");
    },
    {},
    {}};

} // namespace lt
