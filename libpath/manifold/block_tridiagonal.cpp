#include "manifold/block_tridiagonal.h"

#include <algorithm>
#include <cmath>

namespace lt {

Mat2 Mat2::operator*(const Mat2& o) const {
    Mat2 r;
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j)
            r.m[i][j] = m[i][0] * o.m[0][j] + m[i][1] * o.m[1][j];
    return r;
}

Mat2 Mat2::operator-(const Mat2& o) const {
    Mat2 r;
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j)
            r.m[i][j] = m[i][j] - o.m[i][j];
    return r;
}

Mat2 Mat2::operator-() const { return Mat2{} - *this; }

std::array<double, 2> Mat2::operator*(const std::array<double, 2>& v) const {
    return {m[0][0] * v[0] + m[0][1] * v[1], m[1][0] * v[0] + m[1][1] * v[1]};
}

std::optional<Mat2> Mat2::inverse(double relTol) const {
    const double d = det();
    double scale = 0;
    for (const auto& row : m)
        for (double v : row) {
            if (!std::isfinite(v)) return std::nullopt;
            scale = std::max(scale, std::abs(v));
        }
    if (!std::isfinite(d) || !(std::abs(d) > relTol * scale * scale)) return std::nullopt;
    const double inv = 1.0 / d;
    return Mat2{{{{m[1][1] * inv, -m[0][1] * inv}, {-m[1][0] * inv, m[0][0] * inv}}}};
}

std::vector<std::array<double, 2>> BlockTridiagonal::operator*(const std::vector<std::array<double, 2>>& x) const {
    const size_t n = size();
    std::vector<std::array<double, 2>> r(n);
    const auto add = [](std::array<double, 2>& to, const std::array<double, 2>& v) {
        to[0] += v[0];
        to[1] += v[1];
    };
    for (size_t i = 0; i < n; ++i) {
        r[i] = B[i] * x[i];
        if (i > 0) add(r[i], A[i] * x[i - 1]);
        if (i + 1 < n) add(r[i], C[i] * x[i + 1]);
    }
    return r;
}

std::optional<BlockTridiagonalLU> BlockTridiagonalLU::factor(const BlockTridiagonal& J) {
    const size_t n = J.size();
    if (n == 0 || J.A.size() != n || J.C.size() != n) return std::nullopt;
    BlockTridiagonalLU lu;
    lu.A_ = J.A;
    lu.Linv_.resize(n);
    lu.U_.resize(n);
    for (size_t i = 0; i < n; ++i) {
        // Block Thomas: L_1 = B_1, L_i = B_i - A_i U_{i-1}, U_i = L_i^{-1} C_i.
        const Mat2 L = i == 0 ? J.B[0] : J.B[i] - J.A[i] * lu.U_[i - 1];
        const auto Linv = L.inverse();
        if (!Linv) return std::nullopt;
        lu.Linv_[i] = *Linv;
        lu.det_ *= L.det();
        if (i + 1 < n) lu.U_[i] = *Linv * J.C[i];
    }
    if (!std::isfinite(lu.det_)) return std::nullopt;
    return lu;
}

std::vector<std::array<double, 2>> BlockTridiagonalLU::solve(const std::vector<std::array<double, 2>>& b) const {
    const size_t n = Linv_.size();
    std::vector<std::array<double, 2>> y(n);
    for (size_t i = 0; i < n; ++i) {
        std::array<double, 2> r = b[i];
        if (i > 0) {
            const auto ay = A_[i] * y[i - 1];
            r = {r[0] - ay[0], r[1] - ay[1]};
        }
        y[i] = Linv_[i] * r;
    }
    for (size_t i = n - 1; i-- > 0;) {
        const auto ux = U_[i] * y[i + 1];
        y[i] = {y[i][0] - ux[0], y[i][1] - ux[1]};
    }
    return y;
}

double BlockTridiagonalLU::determinant() const { return det_; }

std::vector<Mat2> BlockTridiagonalLU::inverseColumn(size_t k) const {
    // Solve with the identity in block k, one column at a time.
    const size_t n = Linv_.size();
    std::vector<Mat2> out(n);
    for (int c = 0; c < 2; ++c) {
        std::vector<std::array<double, 2>> b(n, {0, 0});
        b[k][size_t(c)] = 1;
        const auto x = solve(b);
        for (size_t i = 0; i < n; ++i) {
            out[i].m[0][size_t(c)] = x[i][0];
            out[i].m[1][size_t(c)] = x[i][1];
        }
    }
    return out;
}

std::vector<Mat2> BlockTridiagonalLU::tangents(const Mat2& lastCoupling) const {
    const size_t n = Linv_.size();
    std::vector<Mat2> out(n);
    for (int c = 0; c < 2; ++c) {
        std::vector<std::array<double, 2>> b(n, {0, 0});
        b[n - 1] = {-lastCoupling.m[0][size_t(c)], -lastCoupling.m[1][size_t(c)]};
        const auto x = solve(b);
        for (size_t i = 0; i < n; ++i) {
            out[i].m[0][size_t(c)] = x[i][0];
            out[i].m[1][size_t(c)] = x[i][1];
        }
    }
    return out;
}

} // namespace lt
