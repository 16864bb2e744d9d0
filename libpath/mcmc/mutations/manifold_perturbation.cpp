#include "mcmc/mutations/manifold_perturbation.h"

#include <algorithm>
#include <sstream>

#include "formats/ltfile.h"
#include "manifold/chains_in_path.h"
#include "util/error.h"
#include "math/frame.h"
#include "math/numeric.h"
#include "manifold/specular_constraint.h"
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

// A light vertex whose position the endpoint move can carry: on an area emitter's shape.
bool movableLight(const PathVertex& v) {
    return v.type == VertexType::Light && !v.infinite && v.emitter && v.emitter->shape >= 0 && v.isOnSurface();
}

} // namespace

ManifoldPerturbation::ManifoldPerturbation(const Scene& scene, double lambda, double normalChange)
    : scene_(scene), sensor_(scene.camera), lambda2_(lambda * lambda), normalChange_(normalChange) {
    if (!(lambda > 0) || !std::isfinite(lambda))
        throw Error("the manifold perturbation's lambda must be a positive number, got " + std::to_string(lambda));
    if (!(normalChange > 0) || !(normalChange <= Pi))
        throw Error("the manifold perturbation's mean normal change must lie in (0, pi], got " +
                    std::to_string(normalChange));
}

double ManifoldPerturbation::specularProbability(const PathVertex& v) const {
    if (v.type != VertexType::Surface || !v.bsdf) return 0; // the path's ends
    if (v.delta) return 1;
    if (!v.bsdf->hasGlossy()) return 0;
    const double alpha = v.bsdf->roughness(v.si.uv);
    if (!std::isfinite(alpha)) return 0; // diffuse
    // 1 - cos(t) as 2 sin^2(t / 2): no cancellation for the small angles of near-specular lobes.
    const auto oneMinusCos = [](double t) { return 2 * sqr(std::sin(t / 2)); };
    const double thetaQ = std::atan(-alpha * alpha * std::log(1 - 0.9));
    const double R = oneMinusCos(thetaQ) / oneMinusCos(std::min(thetaQ + normalChange_, Pi));
    return 1 - std::clamp(R, 0.0, 1.0);
}

double ManifoldPerturbation::stagesProbability(const MarkovPath& path, const Stages& s) const {
    double P = 1;
    for (int i = s.a + s.step();; i += s.step()) {
        const PathVertex& v = path.v[size_t(i)];
        if (!isSpecular(v)) {
            const double psi = specularProbability(v);
            P *= i == s.b || i == s.c ? 1 - psi : psi;
        }
        if (i == s.c) return P;
    }
}

bool ManifoldPerturbation::suitable(const MarkovPath& x) const {
    // x_a, x_b and x_c. A light at infinity is never x_a (stagesFrom) but may be x_c: the walk holds its
    // direction (manifold_vertex.h).
    return nonSpecularCount(x) >= 3;
}

std::optional<ManifoldPerturbation::Stages> ManifoldPerturbation::stagesFrom(const MarkovPath& path, int a, int step) {
    const int k = path.edges();
    // A light at infinity has no position to turn a direction at.
    if (path.v[size_t(a)].infinite) return std::nullopt;
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

std::optional<ManifoldPerturbation::Stages> ManifoldPerturbation::chooseStages(const MarkovPath& x, Pcg32& rng) const {
    const int k = x.edges();
    if (nonSpecularCount(x) < 3) throw Error("manifold perturbation proposed for a path it is not suitable for");
    // x_a and the direction: with 3 non-specular vertices the camera's step toward the light always
    // has its stages, so the loop ends. Whether stages exist depends only on the delta flags and on whether
    // the light is at infinity, which the perturbation keeps: the probability of (a, step) is the same at
    // both states.
    int a = k, step = -1;
    if (!(rng.nextDouble() < 0.25)) {
        std::vector<int> candidates;
        for (int i = 0; i <= k; ++i)
            if (!isSpecular(x.v[size_t(i)])) candidates.push_back(i);
        do {
            const size_t pick = std::min(candidates.size() - 1, size_t(rng.nextDouble() * double(candidates.size())));
            a = candidates[pick];
            step = rng.nextDouble() < 0.5 ? -1 : 1;
        } while (!stagesFrom(x, a, step));
    }
    // The classification: each non-delta vertex passed is specular with probability psi.
    const auto nextNonSpecular = [&](int from) {
        int i = from + step;
        for (; i > 0 && i < k; i += step) {
            const PathVertex& v = x.v[size_t(i)];
            if (isSpecular(v)) continue;
            const double psi = specularProbability(v);
            if (psi == 0 || !(rng.nextDouble() < psi)) break;
        }
        return i;
    };
    Stages s;
    s.a = a;
    // The light's position instead of its direction, half of the time where it can move (a choice that
    // depends on the emitter, which the perturbation keeps).
    if (a == 0 && step == 1 && movableLight(x.v[0]) && rng.nextDouble() < 0.5) {
        s.endpoint = true;
        s.c = nextNonSpecular(0);
        return s;
    }
    s.b = nextNonSpecular(a);
    if (s.b <= 0 || s.b >= k) return std::nullopt;
    s.c = nextNonSpecular(s.b);
    return s;
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

double ManifoldPerturbation::positionSigma(const MarkovPath& path) const {
    const PathVertex& light = path.v[0];
    double pdfPos = 0, pdfDir = 0;
    light.emitter->pdfEmission(light.p(), light.ng(), light.directionTo(path.v[1]), pdfPos, pdfDir);
    return pdfPos > 0 && std::isfinite(pdfPos) ? 1 / std::sqrt(2 * Pi * pdfPos * lambda2_) : 0.0;
}

std::optional<PathVertex> ManifoldPerturbation::movedLight(const MarkovPath& from, const Vec3& d,
                                                           double& density) const {
    const PathVertex& light = from.v[0];
    const Vec3 n = light.ng();
    const double sigma = positionSigma(from);
    // From above the tangent plane (high enough for any curvature the offset spans) straight down.
    const double lift = length(d) + 1e-4 * scene_.bounds.diagonal();
    const auto hit = scene_.intersectHit(Ray{light.p() + d + n * lift, -n});
    if (!(sigma > 0) || !hit || hit->shape != light.emitter->shape) return std::nullopt;
    PathVertex moved = lightVertexAt(scene_, size_t(light.emitterIndex), Vec3(), Vec3(), hit->prim, hit->coords);
    const double cosine = dot(n, moved.ng());
    if (!(cosine > 0)) return std::nullopt; // the other side of the emitter
    density = std::exp(-lengthSquared(d) / (2 * sigma * sigma)) / (2 * Pi * sigma * sigma) * cosine;
    return moved;
}

double ManifoldPerturbation::deltaRunFactor(const MarkovPath& path, int held, int moving) const {
    if (std::abs(held - moving) == 1) return 1;
    const auto chain = manifoldChain(path.v, size_t(held), size_t(moving));
    if (!chain) return 0;
    const auto J = chainJacobian(*chain);
    if (!J) return 0;
    const auto T = tangentMaps(*J);
    if (!T) return 0;
    const double det = std::abs(T->front().det());
    if (!(det > 0) || !std::isfinite(det)) return 0;
    double g = 1;
    const int step = moving > held ? 1 : -1;
    for (int i = held + step; i != moving; i += step)
        g *= geometryTerm(path.v[size_t(i)], path.v[size_t(i + step)]);
    if (held > moving) {
        // The eye end held: G with it held is the eye-to-light term; the light-to-eye one f~ strips
        // differs from it by prod R_rad / R_imp over the run (markov_path.h: the two orientations' deltas
        // differ by that ratio), which holds the refractions' eta^2 and, where a shading normal differs
        // from the geometric one, the adjoint cosine ratio (Veach 1997, Sec. 5.3): not a constant.
        for (int i = moving + 1; i < held; ++i) {
            const PathVertex& x = path.v[size_t(i)];
            const auto imp = deltaImportance(path.v, size_t(i));
            const auto rad = deltaLobe(x, x.directionTo(path.v[size_t(i) + 1]), scatterKind(x), Transport::Radiance);
            if (!imp || !rad || !(rad->pdf > 0)) return 0;
            g *= eyeSideDeltaDensity(*imp, *rad, 1.0) / rad->pdf; // R_imp / R_rad, the lobe fixed as in followChain
        }
    }
    return g / det;
}

double ManifoldPerturbation::deltaRunsFactor(const MarkovPath& path, int from, int to) const {
    const int lo = std::min(from, to), hi = std::max(from, to), k = path.edges();
    double S = 1;
    for (int i = lo; i < hi && S > 0; ++i) {
        if (isSpecular(path.v[size_t(i)]) || !isSpecular(path.v[size_t(i) + 1])) continue;
        int j = i + 1;
        while (isSpecular(path.v[size_t(j)]))
            ++j;
        // Held at the light end, unless the eye end is the camera (no surface to move in).
        S *= j == k ? deltaRunFactor(path, j, i) : deltaRunFactor(path, i, j);
    }
    return S;
}

double ManifoldPerturbation::turnedChainDensity(const MarkovPath& path, const Stages& s, double pdfDir) const {
    const auto& v = path.v;
    double p = v[size_t(s.a)].convertDensity(pdfDir, v[size_t(s.a + s.step())]);
    if (std::abs(s.b - s.a) > 1 && p > 0) {
        const auto chain = manifoldChain(v, size_t(s.a), size_t(s.b));
        const auto J = chain ? chainJacobian(*chain) : std::nullopt;
        const auto T = J ? tangentMaps(*J) : std::nullopt;
        if (!T) return 0;
        p *= std::abs(T->front().det());
    }
    return std::isfinite(p) ? p * deltaRunsFactor(path, s.a, s.b) : 0.0;
}

double ManifoldPerturbation::offsetFactor(const MarkovPath& path, const Stages& s) const {
    const int step = s.step();
    bool holds = false;
    for (int i = s.a + step; i != s.c; i += step)
        holds |= i != s.b && !isSpecular(path.v[size_t(i)]);
    if (!holds) return 1;
    const auto chain = manifoldChain(path.v, size_t(s.a), size_t(s.c));
    if (!chain) return 0;
    std::vector<bool> specular(chain->size());
    for (size_t j = 0; j < chain->size(); ++j)
        specular[j] = isSpecular(path.v[size_t(s.a + step * int(j))]);
    return offsetChartDeterminant(*chain, size_t(std::abs(s.b - s.a)), specular).value_or(0.0);
}

double ManifoldPerturbation::transitionDensity(const MarkovPath& from, const MarkovPath& to, const Stages& s) const {
    if (s.endpoint) {
        // The tangent offset that leads from `from`'s light point to `to`'s, if the projection reaches it.
        const Vec3 n = from.v[0].ng(), diff = to.v[0].p() - from.v[0].p();
        double density = 0;
        const auto reached = movedLight(from, diff - n * dot(diff, n), density);
        if (!reached || !(length(reached->p() - to.v[0].p()) <= ReverseWalkTolerance * scene_.bounds.diagonal()))
            return 0;
        const double J = offsetFactor(to, s);
        return J > 0 ? stagesProbability(from, s) / J * density * deltaRunsFactor(to, s.a, s.c) : 0.0;
    }
    const int next = s.a + s.step();
    const PathVertex& at = from.v[size_t(s.a)];
    const Vec3 was = at.directionTo(from.v[size_t(next)]);
    // The direction the proposal sampled: from the traced ray's origin, which leaves a surface offset
    // along its normal (scene/ray.h); from x_a itself it is off by the offset over the distance, which a
    // near-specular lobe (kappa 1e7) would turn into a density wrong by percents.
    const Vec3& hit = to.v[size_t(next)].p();
    const Vec3 now = normalize(hit - rayFrom(at, hit - at.p()).o);
    const double J = offsetFactor(to, s);
    if (!(J > 0)) return 0;
    return stagesProbability(from, s) / J * turnedChainDensity(to, s, kernel(from, s).density(was, now)) *
           deltaRunsFactor(to, s.b, s.c);
}

std::optional<RejectCause> ManifoldPerturbation::followHeldChain(const MarkovPath& x, MarkovPath& y, const Stages& s,
                                                                 Ray ray) const {
    const auto chain = manifoldChain(x.v, size_t(s.a), size_t(s.b));
    if (!chain) return RejectCause::ConfigurationChanged;
    const int step = s.step();
    for (int i = s.a + step, j = 1;; i += step, ++j) {
        const auto hit = traceVertex(scene_, ray);
        if (!hit) return RejectCause::ConfigurationChanged;
        const PathVertex& was = x.v[size_t(i)];
        PathVertex& v = y.v[size_t(i)];
        v = *hit;
        v.lobe = was.lobe;
        if (i == s.b) {
            v.delta = false;
            return v.isConnectible() ? std::nullopt : std::optional(RejectCause::ConfigurationChanged);
        }
        v.delta = was.delta;
        const ManifoldVertex& old = (*chain)[size_t(j)];
        auto m = manifoldVertex(v.si);
        if (v.si.shape != was.si.shape || !m) return RejectCause::ConfigurationChanged;
        m->scatter = old.scatter;
        m->eta = old.eta;
        m->offset = old.offset;
        const auto out =
            scatterHeld(*m, v.directionTo(y.v[size_t(i - step)]), (*chain)[size_t(j) - 1].seenFrom(old.p), old.ng);
        if (std::holds_alternative<WalkFailure>(out)) return RejectCause::ConfigurationChanged;
        ray = spawnRay(v.si.endpoint(), std::get<Vec3>(out));
    }
}

void ManifoldPerturbation::propose(const MarkovPath& x, Pcg32& rng, Proposal& out) const {
    out.reset();
    std::optional<WalkOutcome>& walk = walkRecord(out);
    walk.reset();
    if (!suitable(x)) throw Error("manifold perturbation proposed for a path it is not suitable for");
    // 1. The stages and the classification.
    const auto s = chooseStages(x, rng);
    if (!s) {
        out.failed = RejectCause::ConfigurationChanged;
        return;
    }
    const int step = s->step();
    const auto holdsGlossy = [&](int from, int to) {
        for (int i = from + step; i != to; i += step)
            if (!isSpecular(x.v[size_t(i)])) return true;
        return false;
    };
    // 2. Turn the direction at x_a and follow the chain after it to x_b', or move the light's position.
    const PathVertex& at = x.v[size_t(s->a)];
    const Vec3 current = at.directionTo(x.v[size_t(s->a + step)]);
    const double u1 = rng.nextDouble(), u2 = rng.nextDouble();
    out.y = x;
    // The density multiplied while sampling (a chain of delta vertices step by step, specular_chain.h; the
    // light's new position from its offset), for the tests' check against transitionDensity; a chain
    // through held glossy vertices has its density only in the closed form of transitionDensity.
    std::optional<double> traced;
    if (s->endpoint) {
        // A 2-D Gaussian offset of standard deviation sigma in the tangent plane.
        const Frame f = Frame::fromNormal(at.ng());
        const auto g = standardNormalPair(u1, u2);
        double sampled = 0;
        const auto light = movedLight(x, (f.s * g[0] + f.t * g[1]) * positionSigma(x), sampled);
        if (!light) {
            out.failed = RejectCause::ConfigurationChanged;
            return;
        }
        out.y.v[0] = *light;
        traced = sampled;
    } else if (!holdsGlossy(s->a, s->b)) {
        const VonMisesFisher lobe = kernel(x, *s);
        const Vec3 dir = lobe.sample(current, u1, u2);
        const double pdfDir = lobe.density(current, dir);
        double sampled = 1;
        const Transport mode = step > 0 ? Transport::Importance : Transport::Radiance;
        if (const auto why = followChain(scene_, x.v, out.y.v, s->a, s->b, rayFrom(at, dir), pdfDir, mode, sampled)) {
            out.failed = why;
            return;
        }
        traced = sampled;
    } else {
        if (const auto why = followHeldChain(x, out.y, *s, rayFrom(at, kernel(x, *s).sample(current, u1, u2)))) {
            out.failed = why;
            return;
        }
    }
    // 3. Walk the chain from x_c (held) to x_b', then back (ME Sec. 5.1 step 4).
    if (std::abs(s->c - s->b) > 1) {
        const auto chain = manifoldChain(x.v, size_t(s->c), size_t(s->b));
        const auto target = manifoldVertex(out.y.v[size_t(s->b)].si);
        if (!chain || !target) { // a degenerate chart: no chain to walk
            walk = WalkOutcome{WalkFailure::Singular, 0, size_t(std::abs(s->c - s->b)) + 1, std::nullopt,
                               JumpOutcome::None};
            out.failed = RejectCause::WalkFailed;
            return;
        }
        const WalkResult walked = walkManifold(scene_, *chain, *target, WalkEnd::Last, walk_);
        walk = WalkOutcome{walked.failure, walked.iterations, chain->size(), std::nullopt, JumpOutcome::None};
        if (!walked.converged()) {
            out.failed = rejectCauseOf(walked.failure);
            return;
        }
        const WalkResult back = reverseWalk(scene_, *chain, walked.chain, WalkEnd::Last, walk_, ReverseWalkTolerance);
        if (!back.converged()) {
            walk->failure = back.failure; // counted as the walk's failure (ME Sec. 5.1 step 4)
            out.failed = rejectCauseOf(back.failure);
            return;
        }
        const int toward = s->b > s->c ? 1 : -1;
        for (size_t j = 1; j + 1 < walked.chain.size(); ++j)
            moveVertex(scene_, walked.chain[j], out.y.v[size_t(s->c + toward * int(j))]);
    }
    if (!evaluateProposal(scene_, x, out)) return;
    // 4. T both ways from the two states (the reverse with y's concentration and classification
    // probability). A chain whose Jacobian is singular at y (x_b' on a caustic fold of x_c), or a
    // specular vertex whose lobe no longer fits after rounding, has no density to accept it with.
    const double walkedRuns = deltaRunsFactor(out.y, s->b, s->c);
    const double J = offsetFactor(out.y, *s);
    if (!(walkedRuns > 0) || !(J > 0)) {
        if (walk) walk->failure = WalkFailure::Singular;
        out.failed = RejectCause::WalkFailed;
        return;
    }
    const double forward = transitionDensity(x, out.y, *s);
    if (!(forward > 0)) {
        out.failed = RejectCause::ConfigurationChanged;
        return;
    }
    const double sampled = traced ? *traced * walkedRuns * stagesProbability(x, *s) / J : forward;
    setTransitionDensities(out, x, sampled, forward, transitionDensity(out.y, x, *s));
}

NormalChange measureNormalChange(const Scene& scene, double lambda, std::span<const MarkovPath> states,
                                 size_t proposals, uint64_t seed, const std::atomic<bool>* stop) {
    const ManifoldPerturbation mutation(scene, lambda);
    std::vector<const MarkovPath*> suitable;
    for (const MarkovPath& x : states)
        if (mutation.suitable(x)) suitable.push_back(&x);
    NormalChange result;
    double sum = 0;
    Pcg32 rng(seed, 0x6d65);
    const auto normalAt = [](const MarkovPath& p, int b) -> std::optional<Vec3> {
        // x_b as the interior of the chain x_{b-1} x_b x_{b+1}: its microfacet normal is its offset's.
        const auto chain = manifoldChain(p.v, size_t(b - 1), size_t(b + 1));
        return chain ? microfacetNormal((*chain)[1], (*chain)[1].offset) : std::nullopt;
    };
    for (; result.proposed < proposals && !suitable.empty(); ++result.proposed) {
        if (stop && stop->load(std::memory_order_relaxed)) break;
        const MarkovPath& x = *suitable[result.proposed % suitable.size()];
        Pcg32 copy = rng;
        const auto s = mutation.chooseStages(x, copy);
        Proposal p;
        mutation.propose(x, rng, p);
        // The light's endpoint move has no x_b between two vertices: no microfacet normal to follow.
        if (p.failed || !s || s->endpoint) continue;
        const auto before = normalAt(x, s->b), after = normalAt(p.y, s->b);
        if (!before || !after) continue;
        sum += std::acos(std::clamp(dot(*before, *after), -1.0, 1.0));
        ++result.measured;
    }
    if (result.measured > 0 && sum > 0) result.radians = std::min(sum / double(result.measured), Pi);
    return result;
}

namespace {

// Proposals of the pre-run (ME App. A1; Mitsuba averages its first 50 000 samples, as here): a fraction of a second.
constexpr size_t NormalChangePreRun = 50000;

// ME App. A1: Delta-theta, which sets how often a glossy vertex is treated as specular, is measured before the
// chains start and then held (an adaptive chain would not be Markov). Without glossy surfaces it is never used.
std::optional<Preparation> preRun(const PrepareContext& c, OptionValues& values) {
    if (!c.features.glossySurfaces) return std::nullopt;
    std::vector<MarkovPath> states;
    for (size_t i = 0; i < c.seeds.size() && states.size() < 4096; ++i) {
        try {
            states.push_back(pathFromRecord(c.scene, c.seeds[i], i));
        } catch (const Error&) { // a seed the scene cannot re-create is left to the run to report
        }
    }
    const NormalChange change =
        measureNormalChange(c.scene, values.number("lambda"), states, NormalChangePreRun, c.seed, c.stop);
    values.put("normal_change", change.radians);
    std::ostringstream message;
    message << "manifold pre-run: " << change.proposed << " proposals, " << change.measured
            << " reached a path; mean normal change at x_b " << radToDeg(change.radians)
            << " degrees (held for the run)";
    return Preparation{file::valueTable("manifold_prerun", {{"proposals", double(change.proposed)},
                                                            {"reached_a_path", double(change.measured)},
                                                            {"normal_change_degrees", radToDeg(change.radians)}}),
                       message.str()};
}

} // namespace

// It walks glossy chains too (their vertices held on offset manifolds, ME Sec. 5.2): on glossy-caustic, auto's
// bidirectional + lens measured relMSE 0.029 at 60 s and with the manifold perturbation added 0.017. It would move
// other paths too, but only as a lens perturbation with quarter-pixel steps; on scenes with specular chains auto
// adds it to Veach's perturbations rather than replacing them (Jakob and Marschner's MEMLT is bidirectional +
// manifold alone): at equal time that mix measured best on veach-bidir's egg and matched MEMLT on caustic-mirror
// (pipelines/results/memlt/README.md).
const MutationKind ManifoldPerturbation::Kind{
    "manifold",
    "perturbation",
    "manifold exploration: turns a direction and walks the specular or glossy chain after it (caustics seen through "
    "glass and mirrors)",
    {{"--lambda", "lambda",
      "manifold perturbation: the direction lobe's peak as lambda^2 times the BSDF's sampling density (default 50; "
      "Jakob & Marschner suggest 50-500: larger takes smaller steps)",
      "FLOAT:POSITIVE", "50", option::positive()}},
    [](const MutationContext& c, const OptionValues& values) -> std::unique_ptr<Mutation> {
        return std::make_unique<ManifoldPerturbation>(
            c.scene, values.number("lambda"), values.has("normal_change") ? values.number("normal_change") : Pi / 180);
    },
    [](const SceneFeatures& f) {
        if (f.specularChains || f.glossySurfaces) return std::string();
        return std::string("no delta or glossy BSDF: no specular or glossy chain to walk");
    },
    preRun,
    {}};

} // namespace lt
