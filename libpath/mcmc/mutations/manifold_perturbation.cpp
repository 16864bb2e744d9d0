#include "mcmc/mutations/manifold_perturbation.h"

#include <algorithm>

#include "manifold/chains_in_path.h"
#include "math/error.h"
#include "path/scatter.h"

namespace lt {

namespace {

// How close (relative to the scene's diagonal) the walk back must bring every vertex to the state's own.
// States re-created from float intersections sit off the exact manifold by up to a few 1e-5 of the
// diagonal once a chain through glass amplifies the rounding (measured on veach-bidir and cornell-spheres:
// 90 % of the misses at 1e-5 were within 4e-5); a walk that lands on another solution of the chain lands
// far away (1e-3 and more in the same runs). 1e-4 leaves 0.3 % of walks non-reversible, as ME Sec. 5.1
// reports (0 - 0.4 %).
constexpr double ReverseWalkTolerance = 1e-4;

constexpr double MaxConcentration = 1e8;

int nonSpecularCount(const MarkovPath& x) {
    return int(std::count_if(x.v.begin(), x.v.end(), [](const PathVertex& v) { return !isSpecular(v); }));
}

RejectCause rejectionOf(WalkFailure f) {
    switch (f) {
    case WalkFailure::Occluded:
        return RejectCause::Occluded;
    case WalkFailure::NonReversible:
        return RejectCause::NotReversible;
    default:
        return RejectCause::WalkFailed;
    }
}

} // namespace

ManifoldPerturbation::ManifoldPerturbation(const Scene& scene, double lambda)
    : scene_(scene), sensor_(scene.camera), lambda2_(lambda * lambda) {
    if (!(lambda > 0) || !std::isfinite(lambda))
        throw Error("the manifold perturbation's lambda must be a positive number, got " + std::to_string(lambda));
}

bool ManifoldPerturbation::suitable(const MarkovPath& x) const {
    // x_a, x_b and x_c; a light at infinity has no position to turn a direction at (lt's chains do not
    // hold such paths yet).
    return nonSpecularCount(x) >= 3 && !x.v[0].infinite;
}

std::optional<ManifoldPerturbation::Stages> ManifoldPerturbation::stagesFrom(const MarkovPath& path, int a, int step) {
    const int k = path.edges();
    const auto nextNonSpecular = [&](int from) {
        int i = from + step;
        while (i >= 0 && i <= k && isSpecular(path.v[size_t(i)]))
            i += step;
        return i;
    };
    Stages s;
    s.a = a;
    s.b = nextNonSpecular(a);
    if (s.b <= 0 || s.b >= k) return std::nullopt; // x_b must be an inner vertex with x_c beyond it
    s.c = nextNonSpecular(s.b);
    if (s.c < 0 || s.c > k) return std::nullopt;
    return s;
}

std::optional<ManifoldPerturbation::Stages> ManifoldPerturbation::chooseStages(const MarkovPath& x, Pcg32& rng) {
    const int k = x.edges();
    if (nonSpecularCount(x) < 3) return std::nullopt;
    // With 3 non-specular vertices the camera's step toward the light always has its stages, so the
    // loop ends.
    if (rng.nextDouble() < 0.25) return stagesFrom(x, k, -1);
    std::vector<int> candidates;
    for (int i = 0; i <= k; ++i)
        if (!isSpecular(x.v[size_t(i)])) candidates.push_back(i);
    for (;;) {
        const size_t pick = std::min(candidates.size() - 1, size_t(rng.nextDouble() * double(candidates.size())));
        if (auto s = stagesFrom(x, candidates[pick], rng.nextDouble() < 0.5 ? -1 : 1)) return s;
    }
}

VonMisesFisher ManifoldPerturbation::kernel(const MarkovPath& path, const Stages& s) const {
    const auto& v = path.v;
    const PathVertex& at = v[size_t(s.a)];
    const PathVertex& next = v[size_t(s.a + s.step())];
    const int back = s.a - s.step();
    const PathVertex* prev = back >= 0 && back < int(v.size()) ? &v[size_t(back)] : nullptr;
    // The sampling density of the current direction in solid angle: the area density PathVertex::pdf
    // gives, converted back.
    const double toArea = at.convertDensity(1.0, next);
    const double p = toArea > 0 ? at.pdf(scene_, prev, next) / toArea : 0.0;
    // At most MaxConcentration: directions rebuilt from float hit points are off by about 1e-7 rad, which
    // a lobe of width 1 / sqrt(kappa) would turn into a density error of sqrt(kappa) 1e-7 (1e-3 here).
    const VonMisesFisher lobe = VonMisesFisher::withPeak(lambda2_ * std::max(p, 1 / (4 * Pi)));
    return {std::min(lobe.kappa, MaxConcentration)};
}

double ManifoldPerturbation::turnedChainDensity(const MarkovPath& path, const Stages& s, double pdfDir) const {
    const auto& v = path.v;
    const int step = s.step();
    double p = v[size_t(s.a)].convertDensity(pdfDir, v[size_t(s.a + step)]);
    for (int i = s.a + 2 * step; i != s.b + step && p > 0; i += step)
        p *= step > 0 ? fixedLobeDensityFromLight(scene_, v, size_t(i))
                      : fixedLobeDensityFromEye(scene_, sensor_, v, size_t(i));
    return p;
}

double ManifoldPerturbation::walkedChainFactor(const MarkovPath& path, const Stages& s) const {
    if (std::abs(s.c - s.b) == 1) return 1;
    const auto chain = manifoldChain(path.v, size_t(s.c), size_t(s.b));
    if (!chain) return 0;
    const auto J = chainJacobian(*chain);
    if (!J) return 0;
    const auto T = tangentMaps(*J);
    if (!T) return 0;
    const double det = std::abs(T->front().det());
    if (!(det > 0) || !std::isfinite(det)) return 0;
    double g = 1;
    const int step = s.b > s.c ? 1 : -1;
    for (int i = s.c + step; i != s.b; i += step)
        g *= geometryTerm(path.v[size_t(i)], path.v[size_t(i + step)]);
    if (s.c > s.b) {
        // x_c on the eye side: G with x_c held is the eye-to-light term; the light-to-eye one f~ strips
        // differs from it by prod R_rad / R_imp over the chain (markov_path.h: the two orientations' deltas
        // differ by that ratio), which holds the refractions' eta^2 and, where a shading normal differs
        // from the geometric one, the adjoint cosine ratio (Veach 1997, Sec. 5.3): not a constant.
        for (int i = s.b + 1; i < s.c; ++i) {
            const PathVertex& x = path.v[size_t(i)];
            const auto imp = deltaImportance(path.v, size_t(i));
            const auto rad = deltaLobe(x, x.directionTo(path.v[size_t(i) + 1]), scatterKind(x), Transport::Radiance);
            if (!imp || !rad || !(rad->pdf > 0)) return 0;
            g *= eyeSideDeltaDensity(*imp, *rad, 1.0) / rad->pdf; // R_imp / R_rad, the lobe fixed as in followChain
        }
    }
    return g / det;
}

double ManifoldPerturbation::transitionDensity(const MarkovPath& from, const MarkovPath& to, const Stages& s) const {
    const int next = s.a + s.step();
    const PathVertex& at = from.v[size_t(s.a)];
    const Vec3 was = at.directionTo(from.v[size_t(next)]);
    // The direction the proposal sampled: from the traced ray's origin, which leaves a surface offset
    // along its normal (scene/ray.h); from x_a itself it is off by the offset over the distance, which a
    // near-specular lobe (kappa 1e7) would turn into a density wrong by percents.
    const Vec3& hit = to.v[size_t(next)].p();
    const Vec3 now = normalize(hit - rayFrom(at, hit - at.p()).o);
    return turnedChainDensity(to, s, kernel(from, s).density(was, now)) * walkedChainFactor(to, s);
}

void ManifoldPerturbation::propose(const MarkovPath& x, Pcg32& rng, Proposal& out) const {
    out = Proposal{};
    // 1. The stages.
    const auto s = chooseStages(x, rng);
    if (!s) throw Error("manifold perturbation proposed for a path it is not suitable for");
    // 2. Turn the direction at x_a and follow the specular vertices after it to x_b'.
    const PathVertex& at = x.v[size_t(s->a)];
    const Vec3 current = at.directionTo(x.v[size_t(s->a + s->step())]);
    const VonMisesFisher lobe = kernel(x, *s);
    const double u1 = rng.nextDouble(), u2 = rng.nextDouble();
    const Vec3 dir = lobe.sample(current, u1, u2);
    const double pdfDir = lobe.density(current, dir);
    out.y = x;
    double sampled = 1;
    const Transport mode = s->step() > 0 ? Transport::Importance : Transport::Radiance;
    if (const auto why = followChain(scene_, x.v, out.y.v, s->a, s->b, rayFrom(at, dir), pdfDir, mode, sampled)) {
        out.failed = why;
        return;
    }
    // 3. Walk the chain from x_c (held) to x_b', then back (ME Sec. 5.1 step 4).
    if (std::abs(s->c - s->b) > 1) {
        const auto chain = manifoldChain(x.v, size_t(s->c), size_t(s->b));
        const auto target = manifoldVertex(out.y.v[size_t(s->b)].si);
        if (!chain || !target) { // a degenerate chart: no chain to walk
            out.walk = WalkOutcome{WalkFailure::Singular, 0, size_t(std::abs(s->c - s->b)) + 1};
            out.failed = RejectCause::WalkFailed;
            return;
        }
        const WalkResult walked = walkManifold(scene_, *chain, *target, WalkEnd::Last, walk_);
        out.walk = WalkOutcome{walked.failure, walked.iterations, chain->size()};
        if (!walked.converged()) {
            out.failed = rejectionOf(walked.failure);
            return;
        }
        const WalkResult back = reverseWalk(scene_, *chain, walked.chain, WalkEnd::Last, walk_, ReverseWalkTolerance);
        if (!back.converged()) {
            out.walk->failure = back.failure; // counted as the walk's failure (ME Sec. 5.1 step 4)
            out.failed = rejectionOf(back.failure);
            return;
        }
        const int step = s->b > s->c ? 1 : -1;
        for (size_t j = 1; j + 1 < walked.chain.size(); ++j) {
            const ManifoldVertex& m = walked.chain[j];
            PathVertex& v = out.y.v[size_t(s->c + step * int(j))];
            const Lobes lobe = v.lobe;
            SurfaceInteraction si = scene_.shapes[size_t(m.shape)].surfaceAt(m.prim, m.coords);
            si.shape = m.shape;
            setSurfaceVertex(scene_, std::move(si), v);
            v.lobe = lobe;
            v.delta = true;
        }
    }
    if (!evaluateProposal(scene_, x, out)) return;
    // 4. T both ways from the two states (the reverse with y's concentration).
    // A walked chain whose Jacobian is singular at y (x_b' on a caustic fold of x_c), or a specular
    // vertex whose lobe no longer fits after rounding, has no density to accept it with.
    const double chainFactor = walkedChainFactor(out.y, *s);
    if (!(chainFactor > 0)) {
        if (out.walk) out.walk->failure = WalkFailure::Singular;
        out.failed = RejectCause::WalkFailed;
        return;
    }
    const double forward = transitionDensity(x, out.y, *s);
    if (!(forward > 0)) {
        out.failed = RejectCause::ConfigurationChanged;
        return;
    }
    setTransitionDensities(out, x, sampled * chainFactor, forward, transitionDensity(out.y, x, *s));
}

} // namespace lt
