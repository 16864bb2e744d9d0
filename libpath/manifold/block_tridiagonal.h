// The block-tridiagonal linear algebra of the manifold walks (Manifold Exploration section 4,
// HSLT section 7): the Jacobian of the specular constraints along a chain of n vertices is
// tridiag(A_i, B_i, C_i) with 2x2 blocks, solved in O(n) by block LU ("block Thomas") in double.
// Singular or non-finite pivots make a solve fail (the caller rejects the proposal); nothing throws.
#pragma once

#include <array>
#include <optional>
#include <vector>

namespace lt {

// A 2x2 matrix, row-major: m[row][column].
struct Mat2 {
    std::array<std::array<double, 2>, 2> m{};

    static Mat2 identity() { return {{{{1, 0}, {0, 1}}}}; }
    [[nodiscard]] double det() const { return m[0][0] * m[1][1] - m[0][1] * m[1][0]; }
    [[nodiscard]] Mat2 operator*(const Mat2& o) const;
    [[nodiscard]] Mat2 operator-(const Mat2& o) const;
    [[nodiscard]] Mat2 operator-() const;
    [[nodiscard]] std::array<double, 2> operator*(const std::array<double, 2>& v) const;
    // The inverse, or nothing when |det| is below `relTol` times the squared largest entry (a pivot
    // that small makes the solve meaningless) or anything is not finite.
    [[nodiscard]] std::optional<Mat2> inverse(double relTol = 1e-12) const;
};

// tridiag(A, B, C): row i couples x_{i-1} (A_i), x_i (B_i) and x_{i+1} (C_i); A_0 and C_{n-1} unused.
struct BlockTridiagonal {
    std::vector<Mat2> A, B, C;
    [[nodiscard]] size_t size() const { return B.size(); }
    // J x, with x as n 2-vectors (HSLT's jump: the constraint values a predicted step reaches to first order).
    [[nodiscard]] std::vector<std::array<double, 2>> operator*(const std::vector<std::array<double, 2>>& x) const;
};

// The block LU factorization L_i = B_i - A_i U_{i-1}, U_i = L_i^{-1} C_i, kept for several solves.
class BlockTridiagonalLU {
public:
    // Nothing when a pivot L_i is singular or non-finite.
    static std::optional<BlockTridiagonalLU> factor(const BlockTridiagonal& J);

    // J x = b, with b and x as n 2-vectors.
    [[nodiscard]] std::vector<std::array<double, 2>> solve(const std::vector<std::array<double, 2>>& b) const;
    // det J = product of det L_i: |dX/dH| = 1 / |det J|.
    [[nodiscard]] double determinant() const;
    // The block column k of J^{-1}: block i of J^{-1} e_k for every i (HSLT's D_i uses one of them).
    [[nodiscard]] std::vector<Mat2> inverseColumn(size_t k) const;
    // Transfer matrices dx_i / dx_end of Manifold Exploration's computeTangents: with the chain's last
    // vertex x_n moved (its coupling C_{n-1}), the constraints stay satisfied when x_i moves by
    // T_i dx_n, where J T = -[0 ... 0 C_{n-1}]^T.
    [[nodiscard]] std::vector<Mat2> tangents(const Mat2& lastCoupling) const;

private:
    std::vector<Mat2> A_, Linv_, U_;
    double det_ = 1;
};

} // namespace lt
