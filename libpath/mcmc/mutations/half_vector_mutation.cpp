#include "mcmc/mutations/half_vector_mutation.h"

#include <algorithm>

#include "manifold/chains_in_path.h"
#include "util/error.h"

namespace lt {

namespace {

// The reverse walk must bring every vertex back within this fraction of the scene diagonal, as the
// manifold perturbation's (manifold_perturbation.cpp: states re-created from float hits sit off their
// exact constraint values by rounding that chains through glass amplify).
constexpr double ReverseWalkTolerance = 1e-4;
// Roughness below this is taken as this: a kernel of zero width would be a delta, not a density.
constexpr double MinRoughness = 1e-6;
// The walk's tolerance is this fraction of gamma alpha / sqrt 2 at the smoothest non-specular vertex (at
// most 1e-7): 1e-3 of the narrowest kernel the state can have (kernels() floors the image-plane limit at
// 1e-3 of it), since the densities are evaluated at the walked state's half vectors, which differ from
// the drawn ones by up to the tolerance. It depends on the materials at the vertices only, not on the
// state's footprint, so that a proposal and its reverse walk with the same tolerance from either state
// (otherwise x -> y could converge where y -> x stops short).
constexpr double ToleranceOfBsdfStep = 1e-6;

// Beckmann-equivalent roughness of a non-specular vertex: the BSDF's, and 1 for diffuse BSDFs (Bsdf::roughness
// reports infinity for them and 0 for a delta coat over a diffuse base) or anything wider (h-perp has at
// most unit length). A rough coat over a diffuse base reports the coat's alpha, whichever lobe the
// vertex scattered by: its diffuse vertices take the coat's narrower steps.
double vertexRoughness(const PathVertex& v) {
    const double a = v.bsdf ? v.bsdf->roughness(v.si.uv) : 1.0;
    return a > 0 && a <= 1 ? std::max(a, MinRoughness) : 1.0;
}

// The principal axes and standard deviations of the columns (a, b): the left singular vectors and
// singular values of [a b], from the eigen-decomposition of [a b][a b]^T.
Gaussian2 principalAxes(const Vec2& a, const Vec2& b) {
    const double sxx = a.x * a.x + b.x * b.x, syy = a.y * a.y + b.y * b.y, sxy = a.x * a.y + b.x * b.y;
    const double mean = 0.5 * (sxx + syy), r = std::hypot(0.5 * (sxx - syy), sxy);
    const double l1 = mean + r, l2 = std::max(mean - r, 0.0);
    Vec2 axis = std::abs(sxy) > 0 ? Vec2(sxy, l1 - sxx) : (sxx >= syy ? Vec2(1, 0) : Vec2(0, 1));
    if (std::abs(sxy) > 0 && std::abs(l1 - sxx) < std::abs(l1 - syy)) axis = Vec2(l1 - syy, sxy);
    return {axis / length(axis), std::sqrt(l1), std::sqrt(l2)};
}

} // namespace

HalfVectorMutation::HalfVectorMutation(const Scene& scene, double gamma, double stratify, bool jumps)
    : scene_(scene), gamma_(gamma), stratify_(stratify), jumps_(jumps) {
    if (!(gamma > 0) || !(gamma <= 1))
        throw Error("the half-vector mutation's gamma must lie in (0, 1], got " + std::to_string(gamma));
    if (!(stratify >= 0) || !std::isfinite(stratify))
        throw Error("the half-vector mutation's image step must be a fraction >= 0, got " + std::to_string(stratify));
}

bool HalfVectorMutation::suitable(const MarkovPath& x) const {
    if (x.v.size() < 3) return false;
    for (size_t i = 1; i + 1 < x.v.size(); ++i)
        if (!isSpecular(x.v[i])) return true;
    return false;
}

std::optional<HalfVectorMutation::State> HalfVectorMutation::state(const MarkovPath& path) const {
    auto chain = manifoldChain(path.v, 0, path.v.size() - 1);
    if (!chain) return std::nullopt;
    auto J = chainJacobian(*chain);
    if (!J) return std::nullopt;
    auto lu = BlockTridiagonalLU::factor(J->A);
    if (!lu) return std::nullopt;
    return State{std::move(*chain), std::move(*J), std::move(*lu)};
}

double HalfVectorMutation::halfVectorFactor(const MarkovPath& path, const State& s) const {
    const size_t n = s.chain.size();
    double g = 1;
    for (size_t j = 1; j + 1 < n; ++j) {
        if (!isSpecular(path.v[j])) continue;
        const Mat2& C = j + 2 < n ? s.J.A.C[j - 1] : s.J.last;
        g *= std::abs(C.det()) / geometryTerm(s.chain[j], s.chain[j + 1]);
    }
    g /= std::abs(s.lu.determinant());
    return g > 0 && std::isfinite(g) ? g : 0.0;
}

std::vector<Gaussian2> HalfVectorMutation::kernels(const MarkovPath& path, const State& s) const {
    const size_t interior = s.chain.size() - 2;
    std::vector<double> alpha(interior, 0.0);
    double alphaSum = 0;
    for (size_t i = 0; i < interior; ++i)
        if (!isSpecular(path.v[i + 1])) alphaSum += alpha[i] = vertexRoughness(path.v[i + 1]);

    // The raster's pixel steps on x_{k-1}'s tangent plane (camera ray differentials, HSLT Sec. 6.2),
    // scaled to `stratify` of the image, in x_{k-1}'s chart.
    std::optional<std::array<std::array<double, 2>, 2>> pixel;
    if (stratify_ > 0) {
        const ManifoldVertex& last = s.chain[s.chain.size() - 2];
        const auto& film = scene_.camera.film();
        const auto onPlane = [&](const Vec2& raster) -> std::optional<Vec3> {
            const Ray r = scene_.camera.generateRay(raster, path.v.back().si.p);
            const double t = planeCrossing(r.o, r.d, last.p, last.ng);
            if (!std::isfinite(t)) return std::nullopt;
            return r.o + r.d * t;
        };
        const auto p0 = onPlane(path.raster), pu = onPlane(path.raster + Vec2(1, 0)),
                   pv = onPlane(path.raster + Vec2(0, 1));
        if (p0 && pu && pv) {
            const Vec3 du = (*pu - *p0) * (stratify_ * film.cropWidth),
                       dv = (*pv - *p0) * (stratify_ * film.cropHeight);
            pixel = {{{dot(du, last.dpdu), dot(du, last.dpdv)}, {dot(dv, last.dpdu), dot(dv, last.dpdv)}}};
        }
    }

    std::vector<Gaussian2> K(interior);
    for (size_t i = 0; i < interior; ++i) {
        if (!(alpha[i] > 0)) continue;
        const double sigmaBsdf = gamma_ * alpha[i] / std::sqrt(2.0);
        K[i] = {{1, 0}, sigmaBsdf, sigmaBsdf};
        if (!pixel) continue;
        // D_i = dx_{k-1} / dh_i (HSLT Eq. 9): block k-1 of J^{-1}'s block column i.
        const auto Dinv = s.lu.inverseColumn(i).back().inverse();
        if (!Dinv) continue;
        const double w = alpha[i] / alphaSum;
        const auto hu = *Dinv * (*pixel)[0], hv = *Dinv * (*pixel)[1];
        Gaussian2 image = principalAxes(Vec2(hu[0], hu[1]) * w, Vec2(hv[0], hv[1]) * w);
        if (!std::isfinite(image.sigma1) || !std::isfinite(image.sigma2) || !isFinite(image.axis)) continue;
        // The smaller step per axis, never below a thousandth of the BSDF's (a degenerate footprint would
        // make the kernel a delta).
        image.sigma1 = std::clamp(image.sigma1, 1e-3 * sigmaBsdf, sigmaBsdf);
        image.sigma2 = std::clamp(image.sigma2, 1e-3 * sigmaBsdf, sigmaBsdf);
        K[i] = image;
    }
    return K;
}

double HalfVectorMutation::transitionDensity(const MarkovPath& from, const MarkovPath& to) const {
    const auto a = state(from), b = state(to);
    if (!a || !b) return 0;
    return kernelTransition(from, *a, kernels(from, *a), *b, halfVectorFactor(to, *b));
}

double HalfVectorMutation::kernelTransition(const MarkovPath& from, const State& a, const std::vector<Gaussian2>& K,
                                            const State& b, double gTo) {
    if (!(gTo > 0)) return 0;
    double T = 1;
    for (size_t i = 0; i < K.size(); ++i)
        if (!isSpecular(from.v[i + 1])) T *= K[i].density(a.J.values[i], b.J.values[i]);
    const double t = T / gTo;
    return std::isfinite(t) ? t : 0.0;
}

bool HalfVectorMutation::jumpable(const MarkovPath& x) const {
    for (size_t i = 1; i + 1 < x.v.size(); ++i)
        if (isSpecular(x.v[i]) || !x.v[i].bsdf) return false;
    // A jump's projections and their density (jumpSubspace's G(y, x'') / G(y, x')) are rays from points.
    return x.v.size() >= 3 && !x.v[0].infinite;
}

double HalfVectorMutation::jumpDensity(const MarkovPath& from, const State& s, const State& to) const {
    const ProjectionOrder order = projectionOrder(s.J);
    const auto pre = jumpPreimage(s.chain, s.J, to.chain, order);
    if (!pre) return 0;
    // Bidirectional invalidity (HSLT Sec. 5.2): `from` jumps only where its regular walk toward the
    // same half vectors fails; where it converges, the pair belongs to the regular move.
    HalfVectorWalkSettings settings = walk_;
    settings.tolerance = walkTolerance(from);
    if (walkHalfVectors(scene_, s.chain, pre->targets, order, settings).converged()) return 0;
    const auto K = kernels(from, s);
    double T = std::abs(s.lu.determinant()) * pre->projection;
    for (size_t i = 0; i < K.size(); ++i)
        T *= K[i].density(s.J.values[i], pre->targets[i]);
    return std::isfinite(T) ? T : 0.0;
}

void HalfVectorMutation::proposeJump(const MarkovPath& x, const State& sx, const std::vector<Vec2>& target,
                                     double sampled, ProjectionOrder order, Proposal& out) const {
    std::optional<WalkOutcome>& walk = walkRecord(out);
    walk->jump = JumpOutcome::Tried;
    const auto jump = jumpSubspace(scene_, sx.chain, sx.J, sx.lu, target, order);
    if (!jump) return;
    Proposal p;
    p.y = x;
    for (size_t j = 1; j + 1 < x.v.size(); ++j) {
        PathVertex& v = p.y.v[j];
        setSurfaceVertex(scene_, SurfaceInteraction(jump->interior[j - 1]), v);
        if (!v.bsdf) return;
        v.delta = false;
        v.lobe = v.bsdf->lobes() & ~LobeDelta;
    }
    if (!evaluateProposal(scene_, x, p)) return;
    const auto sy = state(p.y);
    if (!sy || !jumpable(p.y)) return;
    // T(x -> y) = K(H*) |det J(x)| prod G(y, x'') / G(y, x'): the kernel's density of the drawn half
    // vectors, turned into the predicted points' area density by the affine prediction X' = X + J^{-1}
    // (H* - H) (|dH / dX'| = |det J|, chart area being surface area), then into the hits' (HSLT Sec. 5.2).
    // The reverse jump's density comes from its unique preimage and is 0 unless y's own walk toward it
    // fails too. The ordinary area-measure target stays; no half-vector factor g enters.
    // Both densities from the one function, forward from x's own preimage of y (the drawn half vectors
    // up to rounding; what was sampled is kept for the tests).
    const double forward = jumpDensity(x, sx, *sy), reverse = jumpDensity(p.y, *sy, sx);
    if (!(forward > 0) || !(reverse > 0)) return;
    out.y = std::move(p.y);
    out.failed.reset();
    walk->jump = JumpOutcome::Proposed;
    setTransitionDensities(out, x, sampled * std::abs(sx.lu.determinant()) * jump->projection, forward, reverse);
}

double HalfVectorMutation::walkTolerance(const MarkovPath& path) const {
    double alpha = 1;
    for (size_t i = 1; i + 1 < path.v.size(); ++i)
        if (!isSpecular(path.v[i])) alpha = std::min(alpha, vertexRoughness(path.v[i]));
    return std::min(walk_.tolerance, ToleranceOfBsdfStep * gamma_ * alpha / std::sqrt(2.0));
}

void HalfVectorMutation::propose(const MarkovPath& x, Pcg32& rng, Proposal& out) const {
    out.reset();
    std::optional<WalkOutcome>& walk = walkRecord(out);
    walk.reset();
    out.y = x;
    const auto sx = state(x);
    if (!sx) {
        walk = WalkOutcome{WalkFailure::Singular, 0, x.v.size(), std::nullopt, JumpOutcome::None};
        out.failed = RejectCause::WalkFailed;
        return;
    }
    // 1. New half vectors: drawn at the non-specular vertices, exactly 0 at the specular ones.
    const auto K = kernels(x, *sx);
    std::vector<Vec2> target(K.size()), back(sx->J.values);
    double sampled = 1; // the kernel density of the drawn half vectors
    for (size_t i = 0; i < K.size(); ++i) {
        if (isSpecular(x.v[i + 1])) {
            back[i] = {};
            continue;
        }
        target[i] = K[i].sample(sx->J.values[i], rng);
        sampled *= K[i].density(sx->J.values[i], target[i]);
    }
    HalfVectorWalkSettings settings = walk_;
    settings.tolerance = walkTolerance(x);

    // 2. The vertices with those half vectors, and 3. the walk back (HSLT Fig. 12).
    const ProjectionOrder order = projectionOrder(sx->J);
    const WalkResult walked = walkHalfVectors(scene_, sx->chain, target, order, settings);
    walk = WalkOutcome{walked.failure, walked.iterations, sx->chain.size(), order == ProjectionOrder::FromEye,
                       JumpOutcome::None};
    if (!walked.converged()) {
        out.failed = rejectCauseOf(walked.failure);
        if (jumps_ && jumpable(x)) proposeJump(x, *sx, target, sampled, order, out);
        return;
    }
    const WalkResult rev = reverseHalfVectorWalk(scene_, sx->chain, walked.chain, back, settings, ReverseWalkTolerance);
    if (!rev.converged()) {
        walk->failure = rev.failure;
        out.failed = rejectCauseOf(rev.failure);
        return;
    }
    for (size_t j = 1; j + 1 < walked.chain.size(); ++j)
        moveVertex(scene_, walked.chain[j], out.y.v[j]);
    // A light at infinity keeps its direction; its stored point follows x_1 (path/vertex.h environmentVertex).
    if (out.y.v[0].infinite) out.y.v[0].si.p = scene_.sceneDisk().beyond(out.y.v[1].p(), -out.y.v[0].si.ng);
    // 4. Visibility and f~ of the proposal; 5. T both ways from the two states (each built once).
    if (!evaluateProposal(scene_, x, out)) return;
    const auto sy = state(out.y);
    const double gy = sy ? halfVectorFactor(out.y, *sy) : 0.0;
    const double forward = sy ? kernelTransition(x, *sx, K, *sy, gy) : 0.0;
    if (!(forward > 0) || !(gy > 0)) {
        // J or a C block singular at y, a grazing G, or a kernel density that underflowed: no density.
        walk->failure = WalkFailure::Singular;
        out.failed = RejectCause::WalkFailed;
        return;
    }
    const double reverse = kernelTransition(out.y, *sy, kernels(out.y, *sy), *sx, halfVectorFactor(x, *sx));
    setTransitionDensities(out, x, sampled / gy, forward, reverse);
}

// HSLT mutates every half vector of a path at once (the paper pairs it with the bidirectional mutation alone).
// Added to auto's own mix it did not help at equal time (120 s, 2 cores, relMSE auto against auto + hslt:
// glossy-rings 0.300 / 0.308, veach-mis 0.330 / 0.373, veach-bidir 0.254 / 0.709; pipelines/results/hslt/README.md).
// Its jumps between subspaces are off by default: on glossy-rings they left chains stuck in the corners where a
// ring touches the ground, relMSE 4.8 against 0.37 at 120 s (pipelines/results/hslt/README.md).
const MutationKind HalfVectorMutation::Kind{
    "hslt",
    "mutation",
    "half-vector space light transport: new half vectors at every non-specular vertex at once, the light point or "
    "direction and the camera kept (glossy interreflections)",
    {{"--hslt-gamma", "hslt_gamma",
      "half-vector mutation: its step at each vertex as gamma times the Beckmann lobe's standard deviation (default "
      "0.1, HSLT's value for all its images; in (0, 1])",
      "FLOAT", "0.1", option::number([](double v) { return v > 0 && v <= 1; }, "must lie in (0, 1]")},
     {"--hslt-stratify", "hslt_stratify",
      "half-vector mutation: the image-plane step limiting it, a fraction of the image (default 0.02, HSLT's; 0 "
      "turns the limit off)",
      "FLOAT", "0.02", option::number([](double v) { return v >= 0 && v <= 1; }, "must lie in [0, 1]")},
     {"--hslt-jumps", "hslt_jumps",
      "half-vector mutation: where a walk fails, propose its first prediction projected onto whatever it hits "
      "(HSLT's jumps between subspaces; off by default: on glossy-rings they left chains stuck in the corners where "
      "a ring touches the ground, relMSE 4.8 against 0.37 at 120 s)",
      "on|off", "off", option::onOff}},
    [](const MutationContext& c, const OptionValues& values) -> std::unique_ptr<Mutation> {
        return std::make_unique<HalfVectorMutation>(
            c.scene, values.number("hslt_gamma"), values.number("hslt_stratify"), values.at("hslt_jumps").get<bool>());
    },
    [](const SceneFeatures&) {
        return std::string("measured no better added to auto's mix on glossy, mixed and caustic scenes "
                           "(pipelines/results/hslt); ask for it with --strategies");
    },
    {},
    {}};

} // namespace lt
