// The O(n) block-tridiagonal LU of the manifold walks against a dense solve (Eigen), on random
// well- and ill-conditioned systems; singular systems fail instead of producing NaN.
#include <catch2/catch.hpp>

#include <Eigen/Dense>

#include <cmath>

#include "manifold/block_tridiagonal.h"
#include "math/rng.h"

using namespace lt;

namespace {

Mat2 randomBlock(Pcg32& rng, double scale) {
    Mat2 m;
    for (auto& row : m.m)
        for (double& v : row) v = (2 * rng.nextDouble() - 1) * scale;
    return m;
}

Eigen::MatrixXd dense(const BlockTridiagonal& J) {
    const auto n = Eigen::Index(J.size());
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(2 * n, 2 * n);
    auto put = [&](Eigen::Index bi, Eigen::Index bj, const Mat2& b) {
        for (int r = 0; r < 2; ++r)
            for (int c = 0; c < 2; ++c) M(2 * bi + r, 2 * bj + c) = b.m[size_t(r)][size_t(c)];
    };
    for (Eigen::Index i = 0; i < n; ++i) {
        put(i, i, J.B[size_t(i)]);
        if (i > 0) put(i, i - 1, J.A[size_t(i)]);
        if (i + 1 < n) put(i, i + 1, J.C[size_t(i)]);
    }
    return M;
}

// A random chain of n blocks; `dominance` scales the diagonal blocks (large: well conditioned; near 0:
// ill conditioned).
BlockTridiagonal randomSystem(Pcg32& rng, size_t n, double dominance) {
    BlockTridiagonal J;
    for (size_t i = 0; i < n; ++i) {
        J.A.push_back(randomBlock(rng, 1));
        J.C.push_back(randomBlock(rng, 1));
        Mat2 b = randomBlock(rng, 1);
        b.m[0][0] += dominance;
        b.m[1][1] += dominance;
        J.B.push_back(b);
    }
    return J;
}

} // namespace

TEST_CASE("block-tridiagonal LU agrees with a dense solve", "[manifold]") {
    Pcg32 rng(42, 7);
    for (double dominance : {4.0, 0.3}) {
        for (size_t n : {1u, 2u, 5u, 12u}) {
            CAPTURE(dominance, n);
            const BlockTridiagonal J = randomSystem(rng, n, dominance);
            const auto lu = BlockTridiagonalLU::factor(J);
            REQUIRE(lu);
            const Eigen::MatrixXd M = dense(J);
            Eigen::VectorXd b(2 * Eigen::Index(n));
            std::vector<std::array<double, 2>> bb(n);
            for (size_t i = 0; i < n; ++i) {
                bb[i] = {rng.nextDouble(), rng.nextDouble()};
                b(2 * Eigen::Index(i)) = bb[i][0];
                b(2 * Eigen::Index(i) + 1) = bb[i][1];
            }
            const Eigen::PartialPivLU<Eigen::MatrixXd> ref(M);
            const Eigen::VectorXd x = ref.solve(b);
            const auto y = lu->solve(bb);
            // Backward-stable solves agree to the condition number times the unit round-off.
            const double cond = M.norm() * M.inverse().norm();
            const double tol = 1e3 * cond * 1e-16 * (1 + x.norm());
            for (size_t i = 0; i < n; ++i) {
                CHECK(std::abs(y[i][0] - x(2 * Eigen::Index(i))) < tol);
                CHECK(std::abs(y[i][1] - x(2 * Eigen::Index(i) + 1)) < tol);
            }
            CHECK(lu->determinant() == Approx(ref.determinant()).epsilon(1e3 * cond * 1e-16));
            // A block column of the inverse, and the tangent matrices J T = -[0 .. 0 C]^T.
            const size_t k = n / 2;
            const auto col = lu->inverseColumn(k);
            const Eigen::MatrixXd inv = M.inverse();
            for (size_t i = 0; i < n; ++i)
                for (int r = 0; r < 2; ++r)
                    for (int c = 0; c < 2; ++c)
                        CHECK(std::abs(col[i].m[size_t(r)][size_t(c)] - inv(2 * Eigen::Index(i) + r, 2 * Eigen::Index(k) + c)) <
                              tol * (1 + inv.norm()));
            const Mat2 coupling = randomBlock(rng, 1);
            const auto T = lu->tangents(coupling);
            for (int c = 0; c < 2; ++c) {
                Eigen::VectorXd rhs = Eigen::VectorXd::Zero(2 * Eigen::Index(n));
                rhs(2 * Eigen::Index(n) - 2) = -coupling.m[0][size_t(c)];
                rhs(2 * Eigen::Index(n) - 1) = -coupling.m[1][size_t(c)];
                const Eigen::VectorXd t = ref.solve(rhs);
                for (size_t i = 0; i < n; ++i)
                    for (int r = 0; r < 2; ++r)
                        CHECK(std::abs(T[i].m[size_t(r)][size_t(c)] - t(2 * Eigen::Index(i) + r)) < tol * (1 + t.norm()));
            }
        }
    }
}

TEST_CASE("block-tridiagonal LU fails cleanly on singular and non-finite systems", "[manifold]") {
    Pcg32 rng(3, 1);
    BlockTridiagonal J = randomSystem(rng, 4, 3.0);
    J.B[2] = Mat2{{{{1, 2}, {2, 4}}}};   // rank one
    J.A[2] = Mat2{};
    J.C[1] = Mat2{};                       // decoupled, so the pivot is exactly B_2
    CHECK_FALSE(BlockTridiagonalLU::factor(J));
    BlockTridiagonal K = randomSystem(rng, 3, 3.0);
    K.B[1].m[0][0] = NAN;
    CHECK_FALSE(BlockTridiagonalLU::factor(K));
    CHECK_FALSE(BlockTridiagonalLU::factor(BlockTridiagonal{}));
    CHECK_FALSE(Mat2{{{{1e-20, 0}, {0, 1}}}}.inverse());
    CHECK(Mat2{{{{2, 0}, {0, 4}}}}.inverse()->m[1][1] == 0.25);
}
