#include "manifold/manifold_chain.h"

#include <algorithm>

#include "manifold/specular_constraint.h"
#include "path/vertex.h"

namespace lt {

std::optional<ChainJacobian> chainJacobian(std::span<const ManifoldVertex> chain) {
    if (chain.size() < 3) return std::nullopt;
    ChainJacobian J;
    const size_t n = chain.size() - 2;
    J.A.A.resize(n);
    J.A.B.resize(n);
    J.A.C.resize(n);
    J.values.resize(n);
    for (size_t i = 0; i < n; ++i) {
        const auto row = constraintRow(chain[i], chain[i + 1], chain[i + 2]);
        if (!row) return std::nullopt;
        J.A.A[i] = row->A;
        J.A.B[i] = row->B;
        J.A.C[i] = row->C;
        J.values[i] = row->value;
    }
    // The first row's A and the last row's C couple the endpoints, which are not unknowns of A.
    J.first = J.A.A.front();
    J.last = J.A.C.back();
    J.A.A.front() = Mat2{};
    J.A.C.back() = Mat2{};
    return J;
}

std::optional<std::vector<Mat2>> tangentMaps(const ChainJacobian& J) {
    const auto lu = BlockTridiagonalLU::factor(J.A);
    if (!lu) return std::nullopt;
    auto T = lu->tangents(J.last);
    for (const Mat2& t : T)
        for (const auto& r : t.m)
            if (!std::isfinite(r[0]) || !std::isfinite(r[1])) return std::nullopt;
    return T;
}

double geometryTerm(const ManifoldVertex& a, const ManifoldVertex& b) {
    PathVertex va, vb;
    va.si.p = a.p;
    va.si.ng = a.ng;
    vb.si.p = b.p;
    vb.si.ng = b.ng;
    return geometryTerm(va, vb);
}

ManifoldChain reversed(std::span<const ManifoldVertex> chain) {
    ManifoldChain r(chain.rbegin(), chain.rend());
    // The roles of w_i and w_o swap: eta_o / eta_i inverts. The half vector w_o + w_i / eta is
    // (w_i + eta w_o) / eta, a positive multiple, so the offsets stay as they are.
    for (ManifoldVertex& v : r)
        if (v.scatter == Scatter::Transmission) v.eta = 1 / v.eta;
    return r;
}

std::optional<double> generalizedGeometryTerm(std::span<const ManifoldVertex> chain) {
    if (chain.size() < 2) return std::nullopt;
    if (chain.size() == 2) return geometryTerm(chain[0], chain[1]);
    if (!chain.back().onSurface()) {
        if (!chain.front().onSurface()) return std::nullopt;
        return generalizedGeometryTerm(reversed(chain));
    }
    const auto J = chainJacobian(chain);
    if (!J) return std::nullopt;
    const auto T = tangentMaps(*J);
    if (!T) return std::nullopt;
    // P_2 A^{-1} B_k is -dx_2/dx_k; the sign drops in |det|.
    const double G = std::abs(T->front().det()) * geometryTerm(chain[0], chain[1]);
    return std::isfinite(G) ? std::optional(G) : std::nullopt;
}

} // namespace lt
