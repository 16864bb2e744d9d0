#include "manifold/manifold_chain.h"

#include <algorithm>

#include <Eigen/Dense>

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

std::optional<double> offsetChartDeterminant(std::span<const ManifoldVertex> chain, size_t m,
                                             const std::vector<bool>& specular) {
    if (m >= chain.size() || specular.size() != chain.size()) return std::nullopt;
    const bool interior = m > 0 && m + 1 < chain.size();
    std::vector<size_t> kept; // interior vertices of the chart: m if interior, and those holding an offset
    for (size_t j = 1; j + 1 < chain.size(); ++j)
        if ((interior && j == m) || !specular[j]) kept.push_back(j);
    if (kept.size() == (interior ? 1 : 0)) return 1.0;
    auto J = chainJacobian(chain);
    if (!J) return std::nullopt;
    if (interior) {
        const size_t row = m - 1; // rows of A are the interior vertices 2 .. k-1
        J->A.A[row] = Mat2{};
        J->A.B[row] = Mat2::identity();
        J->A.C[row] = Mat2{};
    }
    const auto lu = BlockTridiagonalLU::factor(J->A);
    if (!lu) return std::nullopt;
    double det = 0;
    if (kept.size() == J->A.size()) {
        det = 1 / std::abs(lu->determinant());
    } else {
        const auto n = Eigen::Index(2 * kept.size());
        Eigen::MatrixXd inv(n, n);
        for (size_t c = 0; c < kept.size(); ++c) {
            const auto column = lu->inverseColumn(kept[c] - 1);
            for (size_t r = 0; r < kept.size(); ++r)
                for (int i = 0; i < 2; ++i)
                    for (int k = 0; k < 2; ++k)
                        inv(Eigen::Index(2 * r) + i, Eigen::Index(2 * c) + k) =
                            column[kept[r] - 1].m[size_t(i)][size_t(k)];
        }
        det = std::abs(inv.determinant());
    }
    return std::isfinite(det) && det > 0 ? std::optional(det) : std::nullopt;
}

double geometryTerm(const ManifoldVertex& a, const ManifoldVertex& b) {
    const auto asPathVertex = [](const ManifoldVertex& m) {
        PathVertex v;
        v.si.p = m.p;
        v.infinite = m.atInfinity;
        v.si.ng = m.atInfinity ? -m.n : m.ng; // at infinity: the direction of travel (path/vertex.h)
        return v;
    };
    return geometryTerm(asPathVertex(a), asPathVertex(b));
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
