#include "manifold/specular_constraint.h"

#include "bsdf/half_vector.h"

namespace lt {

namespace {

// Everything the value and the blocks share: unit directions, inverse distances, the half vector.
struct HalfVectorState {
    Vec3 wi, wo;
    double invDi = 0, invDo = 0;
    Vec3 h;             // the constrained vector: sigma H / |H|, or H itself when index-matched
    double dhScale = 1; // sigma / |H| (1 when index-matched)
    bool normalized = true;
};

std::optional<HalfVectorState> halfVectorState(const ManifoldVertex& prev, const ManifoldVertex& v,
                                               const ManifoldVertex& next) {
    HalfVectorState st;
    const Vec3 di = prev.seenFrom(v.p), dout = next.seenFrom(v.p);
    const double li = length(di), lo = length(dout);
    if (!(li > 0) || !(lo > 0) || !std::isfinite(li) || !std::isfinite(lo)) return std::nullopt;
    const double invLi = 1 / li, invLo = 1 / lo;
    st.wi = di * invLi;
    st.wo = dout * invLo;
    // A direction toward a vertex at infinity does not turn when a vertex moves: inverse distance 0.
    st.invDi = prev.atInfinity ? 0.0 : invLi;
    st.invDo = next.atInfinity ? 0.0 : invLo;
    const Vec3 H = halfVectorUnnormalized(st.wi, st.wo, v.eta);
    if (v.indexMatched()) {
        st.h = H;
        st.normalized = false;
        return st;
    }
    // halfVector() orients h to n's side; sigma is the sign it applied, constant near the solution.
    const auto h = halfVector(st.wi, st.wo, v.eta, v.n);
    if (!h) return std::nullopt;
    st.h = *h;
    st.dhScale = (dot(*h, H) < 0 ? -1.0 : 1.0) / length(H);
    return st;
}

// dh for a change dH of the unnormalized half vector: d(H/|H|) = (dH - h (h.dH)) / |H| (the
// derivative of a normalized vector, math/vec.h), times sigma.
Vec3 dHalf(const HalfVectorState& st, const Vec3& dH) {
    return st.normalized ? normalizedDerivative(st.h, st.dhScale, dH) : dH;
}

// d(unit direction toward x) / d(x moved by delta) = (delta - w (w.delta)) / |x - origin|.
Vec3 dDirection(const Vec3& w, double invDist, const Vec3& delta) { return normalizedDerivative(w, invDist, delta); }

// The 2x2 block whose column k is T^T dh for the k-th chart tangent of the moved vertex.
template <class F> Mat2 block(const ManifoldVertex& v, const Vec3& du, const Vec3& dv, F dh) {
    const Vec2 a = v.frameCoordinates(dh(du)), b = v.frameCoordinates(dh(dv));
    return {{{{a.x, b.x}, {a.y, b.y}}}};
}

} // namespace

std::optional<Vec2> constraintValue(const ManifoldVertex& prev, const ManifoldVertex& v, const ManifoldVertex& next) {
    const auto st = halfVectorState(prev, v, next);
    if (!st) return std::nullopt;
    return v.frameCoordinates(st->h);
}

std::optional<ConstraintRow> constraintRow(const ManifoldVertex& prev, const ManifoldVertex& v,
                                           const ManifoldVertex& next) {
    const auto st = halfVectorState(prev, v, next);
    if (!st) return std::nullopt;
    ConstraintRow row;
    row.value = v.frameCoordinates(st->h);
    // Moving x_{i-1} turns w_i; moving x_{i+1} turns w_o, which enters H with the factor eta (ME App. A2).
    row.A = block(v, prev.dpdu, prev.dpdv, [&](const Vec3& d) { return dHalf(*st, dDirection(st->wi, st->invDi, d)); });
    row.C = block(v, next.dpdu, next.dpdv,
                  [&](const Vec3& d) { return dHalf(*st, dDirection(st->wo, st->invDo, d) * v.eta); });
    // Moving x_i turns both directions (with opposite sign) and rotates the frame: with the field
    // s = a - (a.n) n of manifold_vertex.h (a constant), ds = -(a.dn) n - (a.n) dn (ME section 3.3, dT/du).
    row.B = block(v, v.dpdu, v.dpdv, [&](const Vec3& d) {
        return dHalf(*st, -(dDirection(st->wi, st->invDi, d) + dDirection(st->wo, st->invDo, d) * v.eta));
    });
    const Vec3 dn[2] = {v.dndu, v.dndv};
    const double hn = dot(st->h, v.n);
    for (int k = 0; k < 2; ++k) {
        const double hdn = dot(st->h, dn[k]);
        row.B.m[0][size_t(k)] += -dot(v.frameU, dn[k]) * hn - dot(v.frameU, v.n) * hdn;
        row.B.m[1][size_t(k)] += -dot(v.frameV, dn[k]) * hn - dot(v.frameV, v.n) * hdn;
    }
    return row;
}

bool setScattering(ManifoldVertex& v, const ManifoldVertex& prev, const ManifoldVertex& next,
                   std::optional<InterfaceEta> eta, bool specular) {
    const Vec3 wi = prev.seenFrom(v.p), wo = next.seenFrom(v.p);
    const bool transmission = dot(wi, v.ng) * dot(wo, v.ng) < 0;
    v.scatter = transmission ? Scatter::Transmission : Scatter::Reflection;
    v.eta = 1;
    // A transmission without indices passes straight through (thin dielectric): index-matched, eta = 1.
    if (transmission && eta) {
        const auto side = [&](const Vec3& w) { return dot(w, v.n) > 0 ? eta->exterior : eta->interior; };
        v.eta = side(wo) / side(wi);
    }
    const auto c = constraintValue(prev, v, next);
    if (!c) return false;
    v.offset = specular ? Vec2() : *c;
    return true;
}

} // namespace lt
