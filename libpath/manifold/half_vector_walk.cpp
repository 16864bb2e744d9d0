#include "manifold/half_vector_walk.h"

#include <algorithm>
#include <variant>

namespace lt {

namespace {

double largestError(const std::vector<Vec2>& values, std::span<const Vec2> targets) {
    double e = 0;
    for (size_t i = 0; i < values.size(); ++i)
        e = std::max(e, length(values[i] - targets[i]));
    return e;
}

// The side of v's geometric normal that its neighbour lies on (for a light at infinity, the side its
// fixed direction points to).
double side(const ManifoldVertex& v, const ManifoldVertex& neighbour) { return dot(neighbour.seenFrom(v.p), v.ng); }

// The vertex that projection step `step` (1 .. n-2) places in `order`, and the neighbour its ray starts from.
std::pair<size_t, size_t> projectionStep(size_t n, size_t step, ProjectionOrder order) {
    const bool fromLight = order == ProjectionOrder::FromLight;
    const size_t j = fromLight ? step : n - 1 - step;
    return {j, fromLight ? j - 1 : j + 1};
}

// G(y, x) / G(y, x'), x and x' on one ray from y (the cosine at y cancels): the area density at x per area
// density at x' (HSLT Sec. 5.2), x' on the plane with normal `planeNormal`.
double projectionFactor(const ManifoldVertex& y, const ManifoldVertex& x, const Vec3& predicted,
                        const Vec3& planeNormal) {
    return geometryTerm(y, x) / geometryTerm(y, planeVertex(predicted, planeNormal));
}

// The predicted points projected onto the scene in `order`; the endpoints are kept.
std::variant<ManifoldChain, WalkFailure> project(const Scene& scene, std::span<const ManifoldVertex> X,
                                                 const std::vector<Vec3>& predicted, std::span<const Vec2> targets,
                                                 ProjectionOrder order) {
    ManifoldChain Y(X.begin(), X.end());
    const size_t n = X.size();
    for (size_t step = 1; step + 1 < n; ++step) {
        const auto [j, from] = projectionStep(n, step, order);
        const Ray ray = rayToward(scene, Y[from], predicted[j]);
        const double len = length(ray.d);
        if (!(len > 0)) return WalkFailure::Collapsed;
        const Vec3 dir = ray.d / len;
        ManifoldVertex origin = Y[from];
        origin.p = ray.o;
        const auto si = traceSurface(scene, origin, dir);
        if (!si || si->shape != X[j].shape) {
            const bool nearer = si && si->t < length(predicted[j] - ray.o);
            return nearer ? WalkFailure::Occluded : WalkFailure::LeftSurface;
        }
        // Hit from the side the old segment arrived from.
        if (dot(dir, si->ng) * side(X[j], X[from]) >= 0) return WalkFailure::LeftSurface;
        auto v = manifoldVertex(*si);
        if (!v) return WalkFailure::LeftSurface;
        v->scatter = X[j].scatter;
        v->eta = X[j].eta;
        v->offset = targets[j - 1];
        Y[j] = *v;
    }
    for (size_t j = 1; j + 1 < n; ++j)
        if (side(Y[j], Y[j - 1]) * side(X[j], X[j - 1]) <= 0 || side(Y[j], Y[j + 1]) * side(X[j], X[j + 1]) <= 0)
            return WalkFailure::LeftSurface;
    return Y;
}

} // namespace

ProjectionOrder projectionOrder(const ChainJacobian& J) {
    const auto T = tangentMaps(J);
    if (!T) return ProjectionOrder::FromLight;
    const double first = std::abs(T->front().det()), last = std::abs(T->back().det());
    return first < last ? ProjectionOrder::FromEye : ProjectionOrder::FromLight;
}

WalkResult walkHalfVectors(const Scene& scene, std::span<const ManifoldVertex> chain, std::span<const Vec2> targets,
                           ProjectionOrder order, const HalfVectorWalkSettings& settings) {
    WalkResult res;
    if (chain.size() < 3 || targets.size() + 2 != chain.size()) {
        res.failure = WalkFailure::Collapsed;
        return res;
    }
    ManifoldChain X(chain.begin(), chain.end());
    auto J = chainJacobian(X);
    if (!J) {
        res.failure = WalkFailure::Collapsed;
        return res;
    }
    double err = largestError(J->values, targets);
    double beta = 1;
    WalkFailure lastFailure = WalkFailure::Diverged;
    std::vector<std::array<double, 2>> rhs(targets.size());
    std::vector<Vec3> predicted(X.size());
    while (!(err <= settings.tolerance)) {
        if (res.iterations++ >= settings.maxIterations) {
            res.failure = lastFailure;
            return res;
        }
        const auto lu = BlockTridiagonalLU::factor(J->A);
        if (!lu) {
            res.failure = WalkFailure::Singular;
            return res;
        }
        for (size_t i = 0; i < targets.size(); ++i)
            rhs[i] = {targets[i].x - J->values[i].x, targets[i].y - J->values[i].y};
        const auto dX = lu->solve(rhs);
        for (size_t j = 1; j + 1 < X.size(); ++j)
            predicted[j] = X[j].p + (X[j].dpdu * dX[j - 1][0] + X[j].dpdv * dX[j - 1][1]) * beta;
        auto projected = project(scene, X, predicted, targets, order);
        if (const auto* failure = std::get_if<WalkFailure>(&projected)) {
            lastFailure = *failure;
            beta *= 0.5;
            continue;
        }
        ManifoldChain& Y = std::get<ManifoldChain>(projected);
        auto JY = chainJacobian(Y);
        const double stepErr = JY ? largestError(JY->values, targets) : err;
        if (JY && stepErr < err) {
            X = std::move(Y);
            J = std::move(JY);
            err = stepErr;
            beta = std::min(1.0, 2 * beta);
        } else {
            lastFailure = JY ? WalkFailure::Diverged : WalkFailure::Collapsed;
            beta *= 0.5;
        }
    }
    res.chain = std::move(X);
    return res;
}

WalkResult reverseHalfVectorWalk(const Scene& scene, std::span<const ManifoldVertex> original,
                                 std::span<const ManifoldVertex> walked, std::span<const Vec2> targets,
                                 const HalfVectorWalkSettings& settings, double relativeTolerance) {
    const auto J = chainJacobian(walked);
    if (!J) return {WalkFailure::Collapsed, 0, {}};
    WalkResult r = walkHalfVectors(scene, walked, targets, projectionOrder(*J), settings);
    if (!r.converged()) return r;
    if (!sameChain(r.chain, original, relativeTolerance * scene.bounds.diagonal()))
        r.failure = WalkFailure::NonReversible;
    return r;
}

std::optional<SubspaceJump> jumpSubspace(const Scene& scene, std::span<const ManifoldVertex> chain,
                                         const ChainJacobian& J, const BlockTridiagonalLU& lu,
                                         std::span<const Vec2> targets, ProjectionOrder order) {
    const size_t n = chain.size();
    std::vector<std::array<double, 2>> rhs(targets.size());
    for (size_t i = 0; i < targets.size(); ++i)
        rhs[i] = {targets[i].x - J.values[i].x, targets[i].y - J.values[i].y};
    const auto dX = lu.solve(rhs);
    SubspaceJump jump{std::vector<SurfaceInteraction>(n - 2), 1.0};
    ManifoldChain Y(chain.begin(), chain.end());
    for (size_t step = 1; step + 1 < n; ++step) {
        const auto [j, from] = projectionStep(n, step, order);
        const Vec3 predicted = chain[j].p + chain[j].dpdu * dX[j - 1][0] + chain[j].dpdv * dX[j - 1][1];
        const Vec3 d = predicted - Y[from].p;
        const double len = length(d);
        if (!(len > 0) || !std::isfinite(len)) return std::nullopt;
        const auto si = traceSurface(scene, Y[from], d / len);
        if (!si) return std::nullopt;
        const auto v = manifoldVertex(*si);
        if (!v) return std::nullopt;
        jump.projection *= projectionFactor(Y[from], *v, predicted, chain[j].ng);
        Y[j] = *v;
        jump.interior[j - 1] = *si;
    }
    if (!(jump.projection > 0) || !std::isfinite(jump.projection)) return std::nullopt;
    return jump;
}

std::optional<JumpPreimage> jumpPreimage(std::span<const ManifoldVertex> from, const ChainJacobian& J,
                                         std::span<const ManifoldVertex> to, ProjectionOrder order) {
    const size_t n = from.size();
    if (to.size() != n) return std::nullopt;
    JumpPreimage pre{std::vector<Vec2>(n - 2), 1.0};
    std::vector<std::array<double, 2>> dX(n - 2);
    for (size_t step = 1; step + 1 < n; ++step) {
        const auto [j, prev] = projectionStep(n, step, order);
        const Vec3 d = normalize(to[j].p - to[prev].p);
        const double t = planeCrossing(to[prev].p, d, from[j].p, from[j].ng);
        if (!(t > 0) || !std::isfinite(t)) return std::nullopt;
        const Vec3 predicted = to[prev].p + d * t;
        dX[j - 1] = {dot(predicted - from[j].p, from[j].dpdu), dot(predicted - from[j].p, from[j].dpdv)};
        pre.projection *= projectionFactor(to[prev], to[j], predicted, from[j].ng);
    }
    const auto dH = J.A * dX;
    for (size_t i = 0; i + 2 < n; ++i)
        pre.targets[i] = J.values[i] + Vec2(dH[i][0], dH[i][1]);
    if (!(pre.projection > 0) || !std::isfinite(pre.projection)) return std::nullopt;
    return pre;
}

} // namespace lt
