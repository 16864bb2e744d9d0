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

// The side of v's geometric normal that the point p lies on.
double side(const ManifoldVertex& v, const Vec3& p) { return dot(p - v.p, v.ng); }

// The predicted points projected onto the scene in `order`; the endpoints are kept.
std::variant<ManifoldChain, WalkFailure> project(const Scene& scene, std::span<const ManifoldVertex> X,
                                                 const std::vector<Vec3>& predicted, std::span<const Vec2> targets,
                                                 ProjectionOrder order) {
    ManifoldChain Y(X.begin(), X.end());
    const size_t n = X.size();
    const bool fromLight = order == ProjectionOrder::FromLight;
    for (size_t step = 1; step + 1 < n; ++step) {
        const size_t j = fromLight ? step : n - 1 - step;
        const size_t from = fromLight ? j - 1 : j + 1;
        Vec3 dir = predicted[j] - Y[from].p;
        const double len = length(dir);
        if (!(len > 0)) return WalkFailure::Collapsed;
        dir = dir / len;
        const auto si = traceSurface(scene, Y[from], dir);
        if (!si || si->shape != X[j].shape) return si && si->t < len ? WalkFailure::Occluded : WalkFailure::LeftSurface;
        // Hit from the side the old segment arrived from.
        if (dot(dir, si->ng) * dot(X[j].p - X[from].p, X[j].ng) <= 0) return WalkFailure::LeftSurface;
        auto v = manifoldVertex(*si);
        if (!v) return WalkFailure::LeftSurface;
        v->scatter = X[j].scatter;
        v->eta = X[j].eta;
        v->offset = targets[j - 1];
        Y[j] = *v;
    }
    for (size_t j = 1; j + 1 < n; ++j)
        if (side(Y[j], Y[j - 1].p) * side(X[j], X[j - 1].p) <= 0 ||
            side(Y[j], Y[j + 1].p) * side(X[j], X[j + 1].p) <= 0)
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

} // namespace lt
