#include "manifold/manifold_walk.h"

#include <algorithm>

#include "bsdf/half_vector.h"
#include "path/vertex.h"

namespace lt {

std::string_view walkFailureName(WalkFailure f) {
    switch (f) {
    case WalkFailure::None:
        return "converged";
    case WalkFailure::Diverged:
        return "diverged";
    case WalkFailure::Occluded:
        return "occluded";
    case WalkFailure::TotalInternalReflection:
        return "total internal reflection";
    case WalkFailure::LeftSurface:
        return "left the surface / missed";
    case WalkFailure::Singular:
        return "singular";
    case WalkFailure::Collapsed:
        return "collapsed";
    case WalkFailure::NonReversible:
        return "non-reversible";
    case WalkFailure::Count:
        break;
    }
    return "?";
}

namespace {

// The normal a walk endpoint contributes to the virtual plane: its surface normal, or the axis of a
// point without surface.
Vec3 planeNormalOf(const ManifoldVertex& v) { return v.onSurface() ? v.ng : v.n; }

// ME section 4: n_plane = gamma(gamma(n + n') - d <gamma(n + n'), d>) with d the unit direction from
// x_n to x_n', n flipped first if it faces away from n'; the same plane for x_n -> x_n' and back.
Vec3 virtualPlaneNormal(const ManifoldVertex& from, const ManifoldVertex& to) {
    Vec3 n = planeNormalOf(from);
    const Vec3 n2 = planeNormalOf(to);
    if (dot(n, n2) < 0) n = -n;
    const Vec3 g = normalize(n + n2);
    const Vec3 d = to.p - from.p;
    const double len = length(d);
    if (!(len > 0)) return g;
    const Vec3 dn = d / len;
    const Vec3 q = g - dn * dot(g, dn);
    const double lq = length(q);
    return lq > 1e-12 ? q / lq : g;
}

} // namespace

Ray rayToward(const Scene& scene, const ManifoldVertex& from, const Vec3& toward) {
    if (from.atInfinity) return {scene.sceneDisk().beyond(toward, from.n), -from.n};
    return {from.p, toward - from.p};
}

std::optional<SurfaceInteraction> traceSurface(const Scene& scene, const ManifoldVertex& from, const Vec3& dir) {
    const auto hit = scene.intersectHit(spawnRay(from.endpoint(), dir));
    if (!hit) return std::nullopt;
    const Shape& shape = scene.shapes[size_t(hit->shape)];
    Vec2 coords = hit->coords;
    if (shape.kind() == Shape::Kind::Triangles) {
        // Moeller-Trumbore without the inside test: barycentrics of the plane hit.
        const auto& tri = shape.mesh().triangles[hit->prim];
        const Vec3 p0(shape.mesh().positions[tri[0]]), p1(shape.mesh().positions[tri[1]]),
            p2(shape.mesh().positions[tri[2]]);
        const Vec3 e1 = p1 - p0, e2 = p2 - p0, P = cross(dir, e2), T = from.p - p0, Q = cross(T, e1);
        const double det = dot(e1, P);
        if (std::abs(det) > 0) coords = {dot(T, P) / det, dot(dir, Q) / det};
    } else {
        const double t = shape.intersectAnalytic(from.p, dir, 0.5 * hit->t, 2 * hit->t + 1e-9 * (1 + hit->t));
        if (t > 0) coords = shape.analyticCoords(from.p + dir * t);
    }
    SurfaceInteraction si = shape.surfaceAt(hit->prim, coords);
    si.shape = hit->shape;
    si.t = length(si.p - from.p);
    return si;
}

std::variant<Vec3, WalkFailure> scatterHeld(const ManifoldVertex& v, const Vec3& wi, const Vec3& oldWi,
                                            const Vec3& oldNg) {
    // The configuration must not change: the same side of the surface as before.
    if (dot(wi, v.ng) * dot(oldWi, oldNg) <= 0) return WalkFailure::LeftSurface;
    const auto m = microfacetNormal(v, v.offset);
    if (!m) return WalkFailure::LeftSurface;
    if (v.scatter == Scatter::Reflection) {
        const Vec3 wo = reflect(wi, *m);
        if (dot(wo, v.ng) * dot(wi, v.ng) <= 0) return WalkFailure::LeftSurface;
        return wo;
    }
    const auto wo = refract(wi, *m, v.eta);
    if (!wo) return WalkFailure::TotalInternalReflection;
    if (dot(*wo, v.ng) * dot(wi, v.ng) >= 0) return WalkFailure::LeftSurface;
    return *wo;
}

PropagateResult propagateChain(const Scene& scene, std::span<const ManifoldVertex> X, const Vec3& toward,
                               const ManifoldVertex& plane, double collapse) {
    PropagateResult r;
    r.chain.reserve(X.size());
    r.chain.push_back(X.front());
    const Ray first = rayToward(scene, X.front(), toward);
    ManifoldVertex origin = X.front();
    origin.p = first.o;
    Vec3 dir = normalize(first.d);
    for (size_t j = 1; j + 1 < X.size(); ++j) {
        const ManifoldVertex& prev = j == 1 ? origin : r.chain.back();
        const ManifoldVertex& old = X[j];
        const auto si = traceSurface(scene, prev, dir);
        if (!si || si->shape != old.shape) {
            // Something nearer than the old vertex is in the way; otherwise the ray passed the shape.
            const bool nearer = si && si->t < length(old.p - prev.p);
            r.failure = nearer ? WalkFailure::Occluded : WalkFailure::LeftSurface;
            return r;
        }
        auto v = manifoldVertex(*si);
        if (!v) return {WalkFailure::LeftSurface, {}};
        v->scatter = old.scatter;
        v->eta = old.eta;
        v->offset = old.offset;
        const auto scattered = scatterHeld(*v, -dir, X[j - 1].seenFrom(old.p), old.ng);
        if (const auto* failure = std::get_if<WalkFailure>(&scattered)) return {*failure, {}};
        dir = std::get<Vec3>(scattered);
        r.chain.push_back(*v);
    }
    // The last segment ends on the virtual plane, not on the scene (from `origin` if it is the first).
    const ManifoldVertex& prev = r.chain.size() == 1 ? origin : r.chain.back();
    const double cosPlane = dot(dir, plane.n);
    const double t = planeCrossing(prev.p, dir, plane.p, plane.n);
    if (!(std::abs(cosPlane) > 1e-9) || !(t > 0) || !std::isfinite(t)) return {WalkFailure::LeftSurface, {}};
    ManifoldVertex last = plane;
    last.p = prev.p + dir * t;
    if (length(last.p - prev.p) < collapse) return {WalkFailure::Collapsed, {}};
    r.chain.push_back(last);
    return r;
}

namespace {

WalkResult walkLast(const Scene& scene, ManifoldChain X, const ManifoldVertex& target, const WalkSettings& settings) {
    WalkResult res;
    const double tol = settings.relativeTolerance * std::max(scene.bounds.diagonal(), 1e-300);
    const auto finish = [&](ManifoldChain chain) {
        chain.back() = target;
        const ManifoldVertex& before = chain[chain.size() - 2];
        if (settings.checkVisibility &&
            !(before.atInfinity ? escapes(scene, target.endpoint(), before.n)
                                : unoccluded(scene, before.endpoint(), target.endpoint()))) {
            res.failure = WalkFailure::Occluded;
            return res;
        }
        res.chain = std::move(chain);
        return res;
    };
    if (X.size() == 2) return finish(std::move(X));

    // x_n moves on the virtual plane through itself and the target, with that plane's flat chart.
    const ManifoldVertex plane = planeVertex(X.back().p, virtualPlaneNormal(X.back(), target));
    X.back() = plane;
    double err = length(X.back().p - target.p);
    double beta = 1;
    WalkFailure lastFailure = WalkFailure::Diverged;
    while (err > tol) {
        if (res.iterations++ >= settings.maxIterations) {
            res.failure = lastFailure;
            return res;
        }
        const auto J = chainJacobian(X);
        if (!J) {
            res.failure = WalkFailure::Collapsed;
            return res;
        }
        const auto T = tangentMaps(*J);
        if (!T) {
            res.failure = WalkFailure::Singular;
            return res;
        }
        // Predictor (ME section 4 line 3): x_2 moved in its chart by beta dx_2/dx_n (x_n' - x_n).
        const Vec2 delta = X.back().frameCoordinates(target.p - X.back().p);
        const auto d2 = T->front() * std::array<double, 2>{delta.x, delta.y};
        const Vec3 p2 = X[1].p + (X[1].dpdu * d2[0] + X[1].dpdv * d2[1]) * beta;
        PropagateResult step = propagateChain(scene, X, p2, plane, tol);
        const double stepErr = step.failure == WalkFailure::None ? length(step.chain.back().p - target.p) : err;
        if (step.failure == WalkFailure::None && stepErr < err) {
            X = std::move(step.chain);
            err = stepErr;
            beta = std::min(1.0, 2 * beta);
        } else {
            lastFailure = step.failure == WalkFailure::None ? WalkFailure::Diverged : step.failure;
            beta *= 0.5;
        }
    }
    return finish(std::move(X));
}

} // namespace

WalkResult walkManifold(const Scene& scene, std::span<const ManifoldVertex> chain, const ManifoldVertex& target,
                        WalkEnd moving, const WalkSettings& settings) {
    if (chain.size() < 2) return {WalkFailure::Collapsed, 0, {}};
    if (moving == WalkEnd::Last) return walkLast(scene, ManifoldChain(chain.begin(), chain.end()), target, settings);
    WalkResult r = walkLast(scene, reversed(chain), target, settings);
    if (r.converged()) r.chain = reversed(r.chain);
    return r;
}

WalkResult reverseWalk(const Scene& scene, std::span<const ManifoldVertex> original,
                       std::span<const ManifoldVertex> walked, WalkEnd moving, const WalkSettings& settings,
                       double relativeTolerance) {
    const ManifoldVertex& start = moving == WalkEnd::Last ? original.back() : original.front();
    WalkResult r = walkManifold(scene, walked, start, moving, settings);
    if (!r.converged()) return r;
    if (!sameChain(r.chain, original, relativeTolerance * scene.bounds.diagonal()))
        r.failure = WalkFailure::NonReversible;
    return r;
}

bool sameChain(std::span<const ManifoldVertex> a, std::span<const ManifoldVertex> b, double tolerance) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
        if (!(length(a[i].p - b[i].p) <= tolerance)) return false;
    return true;
}

} // namespace lt
