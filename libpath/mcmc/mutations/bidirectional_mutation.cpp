#include "mcmc/mutations/bidirectional_mutation.h"

#include <cmath>
#include <cstdlib>

#include "bsdf/shading_correction.h"
#include "math/frame.h"
#include "mcmc/mutations/trace.h"

namespace lt {

namespace {

constexpr int MaxLengthChange = 8;

double geometricWeight(int a, int b) { return std::ldexp(1.0, -std::abs(a - b)); }

// A connection joins two vertices through their non-delta lobes (BDPT's rule).
bool connectible(const PathVertex& v) {
    if (v.type == VertexType::Surface) return !isSpecular(v) && v.isConnectible();
    return v.isConnectible();
}

// The first admissible range start for kd deleted edges: l = -1 (the light vertex re-sampled) needs a
// light that can move and at least the light vertex in the range.
int lowestStart(bool lightMovable, int kd) { return lightMovable && kd >= 2 ? -1 : 0; }

// A light vertex the mutation can sample anew: on an area emitter, or a direction of the environment (a
// point or spot light's position and a directional light's direction are deltas: never re-sampled).
bool movableEmitter(const Emitter& e) { return e.shape >= 0 || (e.isInfinite() && !e.isDelta()); }

} // namespace

BidirectionalMutation::BidirectionalMutation(const Scene& scene, int maxEdges, int minEdges)
    : scene_(scene), maxEdges_(maxEdges), minEdges_(minEdges), sensor_(scene.camera), cameraMovable_(scene.camera.hasAperture()) {
    std::vector<double> weights(scene.emitters.size(), 0.0);
    for (size_t i = 0; i < scene.emitters.size(); ++i)
        if (movableEmitter(*scene.emitters[i])) movableEmitterMass_ += weights[i] = scene.emitterSelection.pmf(i);
    movableSelection_ = DiscreteDistribution(weights);
}

bool BidirectionalMutation::lightMovable(const MarkovPath& path) const {
    return movableEmitterMass_ > 0 && path.v[0].emitter && movableEmitter(*path.v[0].emitter);
}

double BidirectionalMutation::deletedProbability(int k, bool lightMovable, int kd) const {
    const int kdMax = k + int(lightMovable) + int(cameraMovable_);
    if (kd < 1 || kd > kdMax) return 0;
    double sum = 0;
    for (int j = 1; j <= kdMax; ++j)
        sum += geometricWeight(j, 2);
    return geometricWeight(kd, 2) / sum;
}

double BidirectionalMutation::addedProbability(int k, int kd, int l, int ka) const {
    // New vertices a - 1: at least the light vertex if it was deleted, and the camera vertex if it was.
    const int endpoints = int(l == -1) + int(l + kd == k + 1);
    auto admissible = [&](int a) {
        const int length = k - kd + a;
        return a >= 1 && std::abs(a - kd) <= MaxLengthChange && length >= minEdges_ && length <= maxEdges_ &&
               !(kd == 1 && a == 1) && a - 1 >= endpoints;
    };
    if (!admissible(ka)) return 0;
    double sum = 0;
    for (int a = std::max(1, kd - MaxLengthChange); a <= kd + MaxLengthChange; ++a)
        if (admissible(a)) sum += geometricWeight(a, kd);
    return geometricWeight(ka, kd) / sum;
}

double BidirectionalMutation::rangeProbability(int k, bool lightMovable, int kd, int l, int ka) const {
    const int lmin = lowestStart(lightMovable, kd), lmax = highestStart(k, kd);
    if (l < lmin || l > lmax) return 0;
    return deletedProbability(k, lightMovable, kd) / double(lmax - lmin + 1) * addedProbability(k, kd, l, ka);
}

double BidirectionalMutation::newVertexDensity(const MarkovPath& path, int lo, int hi, int split,
                                               double* splitDensity) const {
    const auto& v = path.v;
    const int n = hi - lo + 1;
    double sum = 0;
    for (int s = 0; s <= n; ++s) {
        const int c = lo + s; // the first vertex sampled from the eye side; the connection is (c - 1, c)
        double p = 0;
        // c = k + 1: every new vertex from the light side, the camera vertex too, which no light subpath reaches.
        if (c < int(v.size()) && (c == 0 || (connectible(v[size_t(c) - 1]) && connectible(v[size_t(c)])))) {
            p = 1;
            for (int i = lo; i < c && p > 0; ++i)
                p *= i == 0 ? densityFromLight(scene_, v, 0) / movableEmitterMass_
                            : densityFromLight(scene_, v, size_t(i));
            for (int i = c; i <= hi && p > 0; ++i)
                p *= densityFromEye(scene_, sensor_, v, size_t(i));
        }
        if (s == split && splitDensity) *splitDensity = p;
        sum += p;
    }
    return sum / double(n + 1);
}

std::optional<BidirectionalMutation::Range> BidirectionalMutation::chooseRange(int k, bool movable, Pcg32& rng) const {
    // The range and the new length: kd by inversion, l uniform, ka by inversion.
    Range r;
    {
        double u = rng.nextDouble();
        const int kdMax = k + int(movable) + int(cameraMovable_);
        for (r.kd = 1; r.kd < kdMax; ++r.kd) {
            u -= deletedProbability(k, movable, r.kd);
            if (u < 0) break;
        }
    }
    const int lmin = lowestStart(movable, r.kd), lmax = highestStart(k, r.kd);
    r.l = lmin + std::min(int(rng.nextDouble() * (lmax - lmin + 1)), lmax - lmin);
    r.m = r.l + r.kd;
    double u = rng.nextDouble();
    for (int a = std::max(1, r.kd - MaxLengthChange); a <= r.kd + MaxLengthChange && r.ka == 0; ++a) {
        const double p = addedProbability(k, r.kd, r.l, a);
        if (p > 0 && (u -= p) < 0) r.ka = a;
    }
    // No admissible length (the path is at the maximum and nothing may be inserted): no proposal.
    if (r.ka == 0) return std::nullopt;
    r.s = std::min(int(rng.nextDouble() * r.ka), r.ka - 1); // light-side new vertices
    r.t = r.ka - 1 - r.s;                                   // eye-side new vertices
    return r;
}

std::optional<RejectCause> BidirectionalMutation::sampleLightSide(const Range& r, Pcg32& rng,
                                                                  std::vector<PathVertex>& light,
                                                                  double& sampled) const {
    for (int i = 0; i < r.s; ++i) {
        if (light.empty()) {
            // The light vertex anew: a point on an area emitter, or a direction of the environment (in
            // solid angle, as densityFromLight has it; the edge to it then needs no direction from x_1).
            // The emitter is chosen among the movable ones only, with the probability newVertexDensity
            // gives (pmf / movableEmitterMass_): a draw among all that failed on a point light would make
            // the light-side splits' true density pmf, not pmf / mass, against the eye-side split's.
            if (movableSelection_.empty()) return RejectCause::ZeroContribution;
            const size_t index = movableSelection_.sample(rng.nextDouble());
            const Emitter& e = *scene_.emitters[index];
            if (!movableEmitter(e)) return RejectCause::ZeroContribution;
            const Vec2 uPos(rng.nextDouble(), rng.nextDouble()), uDir(rng.nextDouble(), rng.nextDouble());
            const EmissionSample es = e.sampleEmission(uPos, uDir);
            if (!(es.pdfPos > 0) || !(es.pdfDir > 0)) return RejectCause::ZeroContribution;
            const double pmf = movableSelection_.pmf(index);
            if (e.isInfinite()) {
                light.push_back(environmentVertex(scene_, scene_.sceneDisk().center, -es.d));
                sampled *= pmf * es.pdfDir;
            } else {
                light.push_back(lightVertexAt(scene_, index, es.p, es.n, es.prim, es.coords));
                sampled *= pmf * es.pdfPos;
            }
            continue;
        }
        PathVertex& from = light.back();
        Vec3 dir;
        double pdfArea = 0;
        std::optional<PathVertex> next;
        if (light.size() == 1 && from.infinite) {
            // Emission from a direction of the environment: the light keeps its direction and enters at a
            // point uniform on the scene's disk across it (the density pdfLight gives).
            next =
                traceVertex(scene_, Ray{scene_.sceneDisk().sample(Vec2(rng.nextDouble(), rng.nextDouble()), from.si.ng),
                                        from.si.ng});
            if (!next) return RejectCause::ZeroContribution;
            pdfArea = from.pdfLight(scene_, *next);
        } else if (light.size() == 1) {
            // Emission from the light vertex: its direction law (cosine for area emitters) around its own
            // normal, drawn from the emitter's sampler and carried into this vertex's frame.
            const Vec2 uPos(rng.nextDouble(), rng.nextDouble()), uDir(rng.nextDouble(), rng.nextDouble());
            const EmissionSample es = from.emitter->sampleEmission(uPos, uDir);
            dir = from.isOnSurface() ? Frame::fromNormal(from.si.ng).toWorld(Frame::fromNormal(es.n).toLocal(es.d))
                                     : es.d;
            next = traceVertex(scene_, rayFrom(from, dir));
            if (!next) return RejectCause::ZeroContribution;
            pdfArea = from.pdfLight(scene_, *next);
        } else {
            if (!from.bsdf) return RejectCause::ZeroContribution;
            const PathVertex& prev = light[light.size() - 2];
            from.wi = from.directionTo(prev);
            const double uLobe = rng.nextDouble();
            const auto bs =
                sampleScattering(from, from.wi, Transport::Importance, uLobe, Vec2(rng.nextDouble(), rng.nextDouble()));
            if (!bs) return RejectCause::ZeroContribution;
            next = traceVertex(scene_, rayFrom(from, bs->wo));
            if (!next) return RejectCause::ZeroContribution;
            pdfArea = from.delta ? bs->pdf * geometryTerm(from, *next) : from.convertDensity(bs->pdf, *next);
        }
        sampled *= pdfArea;
        light.push_back(*next);
    }
    return std::nullopt;
}

std::optional<RejectCause> BidirectionalMutation::sampleEyeSide(const MarkovPath& x, const Range& r, bool lightDeleted,
                                                                Pcg32& rng, std::vector<PathVertex>& eye,
                                                                double& sampled) const {
    for (int i = 0; i < r.t; ++i) {
        if (eye.empty()) {
            // The camera vertex anew: a point uniform on the thin lens's aperture (densityFromEye at k).
            PathVertex camera = x.v.back();
            camera.si.p = scene_.camera.sampleLens(Vec2(rng.nextDouble(), rng.nextDouble()));
            sampled /= scene_.camera.lensArea();
            eye.push_back(camera);
            continue;
        }
        PathVertex& from = eye.back();
        std::optional<PathVertex> next;
        double pdfArea = 0;
        // The last eye-side vertex of a path whose light vertex is re-sampled from the eye may be the sky.
        const bool escape = lightDeleted && i + 1 == r.t;
        if (from.type == VertexType::Camera) {
            auto traced = traceFromCamera(scene_, sensor_, from, rng, escape);
            if (!traced) return RejectCause::ZeroContribution;
            next = std::move(traced->v);
            pdfArea = traced->density;
        } else {
            if (!from.bsdf) return RejectCause::ZeroContribution;
            const PathVertex& toward = eye[eye.size() - 2];
            const Vec3 wEye = from.directionTo(toward);
            const double uLobe = rng.nextDouble();
            const auto bs =
                sampleScattering(from, wEye, Transport::Radiance, uLobe, Vec2(rng.nextDouble(), rng.nextDouble()));
            if (!bs) return RejectCause::ZeroContribution;
            next = traceOrEscape(scene_, rayFrom(from, bs->wo), escape);
            if (!next) return RejectCause::ZeroContribution;
            if (from.delta) {
                // The light-to-eye delta differs from the sampled one by R_imp / weight_rad (markov_path.h).
                const auto imp = from.worldBsdf().deltaEval(bs->wo, wEye, Transport::Importance);
                if (!imp) return RejectCause::ZeroContribution;
                pdfArea = eyeSideDeltaDensity(*imp, *bs, geometryTerm(from, *next));
            } else {
                pdfArea = from.convertDensity(bs->pdf, *next);
            }
        }
        sampled *= pdfArea;
        eye.push_back(*next);
    }
    return std::nullopt;
}

void BidirectionalMutation::propose(const MarkovPath& x, Pcg32& rng, Proposal& out) const {
    out.reset();
    const int k = x.edges();
    const bool movable = lightMovable(x);
    // 1. The range and the new length.
    const auto range = chooseRange(k, movable, rng);
    if (!range) {
        out.failed = RejectCause::ZeroContribution;
        return;
    }
    const Range& r = *range;
    // 2. Sample the new vertices. `light` holds the prefix and the light-side vertices, `eye` the suffix
    // and the eye-side vertices in eye-to-light order.
    std::vector<PathVertex> light(x.v.begin(), x.v.begin() + (r.l + 1));
    std::vector<PathVertex> eye(x.v.rbegin(), x.v.rbegin() + (k - r.m + 1));
    double sampled = 1;
    if ((out.failed = sampleLightSide(r, rng, light, sampled))) return;
    if ((out.failed = sampleEyeSide(x, r, light.empty(), rng, eye, sampled))) return;
    const auto fail = [&] { out.failed = RejectCause::ZeroContribution; };
    // 3. Join: the eye side reached the light (l = -1, s = 0), or a deterministic connection. A deleted
    // camera vertex comes from the eye side only (no light subpath reaches a lens).
    if (eye.empty()) return fail();
    if (light.empty()) {
        PathVertex& end = eye.back();
        if (!end.infinite) {
            auto light = asLightVertex(scene_, end);
            if (!light) return fail();
            end = std::move(*light);
        }
    } else {
        light.back().delta = false;
        eye.back().delta = false;
        if (!connectible(light.back()) || !connectible(eye.back())) return fail();
    }
    out.y.v = std::move(light);
    out.y.v.insert(out.y.v.end(), eye.rbegin(), eye.rend());
    if (!evaluateProposal(scene_, x, out)) return;

    // 4. Q in both directions, from the two paths alone.
    const int kNew = out.y.edges();
    double splitDensity = 0;
    const double forward = newVertexDensity(out.y, r.l + 1, r.l + r.ka - 1, r.s, &splitDensity);
    const double reverse = newVertexDensity(x, r.l + 1, r.m - 1);
    out.forwardQ = rangeProbability(k, movable, r.kd, r.l, r.ka) * forward / out.y.target;
    out.reverseQ = rangeProbability(kNew, lightMovable(out.y), r.ka, r.l, r.kd) * reverse / x.target;
    out.sampledDensity = sampled;
    out.recomputedDensity = splitDensity;
}

// Always in `auto`'s mix: the one mutation that can replace any part of a path (ergodicity; MCMC survey, Sec. 3.3).
const MutationKind BidirectionalMutation::Kind{
    "bidirectional",
    "mutation",
    "replaces any part of a path; required: the others alone are not ergodic",
    {},
    [](const MutationContext& c, const OptionValues&) -> std::unique_ptr<Mutation> {
        return std::make_unique<BidirectionalMutation>(c.scene, c.maxEdges, c.minEdges);
    },
    [](const SceneFeatures&) { return std::string(); },
    {},
    {}};

} // namespace lt
