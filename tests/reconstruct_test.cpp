// reconstruct/: the screened Poisson reconstruction: exact recovery from exact
// gradients, Ceres, Eigen CG and the cosine transform against an Eigen sparse solve of the normal
// equations, Eigen CG against Ceres for L1, auto's choice of solver, unbiasedness of L2 over many noise
// draws against the variance the linear solve implies, L1's robustness to outliers (also with the cosine
// transform's solver forced), the offset equivariance, stiff cases, the direct plane, and the messages for
// bad input.
#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <catch2/catch.hpp>

#include "test_util.h"
#include <cmath>
#include <functional>
#include <limits>

#include "util/error.h"
#include "math/rng.h"
#include "reconstruct/dct_poisson.h"
#include "reconstruct/gradient_image.h"
#include "reconstruct/normal_equations.h"
#include "reconstruct/screened_poisson.h"

using namespace lt;

namespace {

// A smooth RGB image, values about 0.5 .. 2, different in each channel.
RgbPlanes smoothImage(uint32_t w, uint32_t h) {
    RgbPlanes img;
    for (size_t c = 0; c < 3; ++c) {
        img[c].resize(size_t(w) * h);
        for (uint32_t y = 0; y < h; ++y)
            for (uint32_t x = 0; x < w; ++x)
                img[c][size_t(y) * w + x] =
                    float(1.2 + 0.5 * std::sin(0.21 * x + 0.5 * c) * std::cos(0.17 * y - 0.3 * c) + 0.01 * x);
    }
    return img;
}

// The gradient image of `truth` with exact primal and gradients.
GradientImage exactInput(const RgbPlanes& truth, uint32_t w, uint32_t h) {
    GradientImage im;
    im.width = w;
    im.height = h;
    im.primal = truth;
    forwardDifferences(truth, w, h, im.dx, im.dy);
    return im;
}

void addNoise(GradientImage& im, Pcg32& rng, double sigmaPrimal, double sigmaGradient) {
    for (size_t c = 0; c < 3; ++c)
        for (size_t p = 0; p < im.pixels(); ++p) {
            im.primal[c][p] += float(sigmaPrimal * standardNormal(rng));
            im.dx[c][p] += float(sigmaGradient * standardNormal(rng));
            im.dy[c][p] += float(sigmaGradient * standardNormal(rng));
        }
}

file::Buffer solve(const GradientImage& im, ReconstructNorm norm, double alpha,
                   PoissonSolver solver = PoissonSolver::Auto, int maxLinearIterations = 0) {
    ReconstructSettings s;
    s.norm = norm;
    s.alpha = alpha;
    s.solver = solver;
    s.maxLinearIterations = maxLinearIterations;
    ReconstructStatistics stats;
    return reconstructScreenedPoisson(im, s, stats);
}

double maxRelativeError(const file::Buffer& out, const RgbPlanes& truth) {
    double worst = 0;
    for (size_t c = 0; c < 3; ++c)
        for (size_t p = 0; p < truth[c].size(); ++p)
            worst = std::max(worst, std::abs(double(out.planes[c][p]) - truth[c][p]) /
                                        std::max(1.0, std::abs(double(truth[c][p]))));
    return worst;
}

// The largest over the channels of |out - ref|_2 / |ref|_2.
double relativeNormError(const file::Buffer& out, const RgbPlanes& ref) {
    double worst = 0;
    for (size_t c = 0; c < 3; ++c) {
        double diff = 0, norm = 0;
        for (size_t p = 0; p < ref[c].size(); ++p) {
            diff += std::pow(double(out.planes[c][p]) - ref[c][p], 2);
            norm += std::pow(double(ref[c][p]), 2);
        }
        worst = std::max(worst, std::sqrt(diff / norm));
    }
    return worst;
}

double rmse(const file::Buffer& out, const RgbPlanes& truth) {
    double sum = 0;
    for (size_t c = 0; c < 3; ++c)
        for (size_t p = 0; p < truth[c].size(); ++p)
            sum += std::pow(double(out.planes[c][p]) - truth[c][p], 2);
    return std::sqrt(sum / (3.0 * truth[0].size()));
}

bool allFinite(const file::Buffer& b) {
    for (const auto& plane : b.planes)
        for (float v : plane)
            if (!std::isfinite(v)) return false;
    return true;
}

// The forward-difference operators as sparse matrices, one row per difference inside the image (the
// last column of Dx and last row of Dy are absent: those differences would leave the image).
struct Operators {
    Eigen::SparseMatrix<double> Dx, Dy;
    std::vector<size_t> xRows, yRows; // the pixel each row belongs to
};
Operators differenceOperators(uint32_t w, uint32_t h) {
    Operators op;
    std::vector<Eigen::Triplet<double>> tx, ty;
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            const int p = int(y * w + x);
            if (x + 1 < w) {
                const int r = int(op.xRows.size());
                tx.emplace_back(r, p, -1.0);
                tx.emplace_back(r, p + 1, 1.0);
                op.xRows.push_back(size_t(p));
            }
            if (y + 1 < h) {
                const int r = int(op.yRows.size());
                ty.emplace_back(r, p, -1.0);
                ty.emplace_back(r, p + int(w), 1.0);
                op.yRows.push_back(size_t(p));
            }
        }
    const int n = int(w * h);
    op.Dx.resize(int(op.xRows.size()), n);
    op.Dy.resize(int(op.yRows.size()), n);
    op.Dx.setFromTriplets(tx.begin(), tx.end());
    op.Dy.setFromTriplets(ty.begin(), ty.end());
    return op;
}

// The normal equations of the L2 problem, (alpha^2 1 + Dx^T Dx + Dy^T Dy) I = alpha^2 P + Dx^T Gx + Dy^T Gy,
// solved by Eigen's sparse LDL^T in double precision: an independent reference for
// Ceres and the cosine transform.
std::array<Eigen::VectorXd, 3> referenceSolution(const GradientImage& im, double alpha) {
    const Operators op = differenceOperators(im.width, im.height);
    const int n = int(im.pixels());
    Eigen::SparseMatrix<double> I(n, n);
    I.setIdentity();
    const Eigen::SparseMatrix<double> A = alpha * alpha * I + Eigen::SparseMatrix<double>(op.Dx.transpose() * op.Dx) +
                                          Eigen::SparseMatrix<double>(op.Dy.transpose() * op.Dy);
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(A);
    REQUIRE(ldlt.info() == Eigen::Success);
    std::array<Eigen::VectorXd, 3> out;
    for (size_t c = 0; c < 3; ++c) {
        Eigen::VectorXd P(n), gx(op.Dx.rows()), gy(op.Dy.rows());
        for (int p = 0; p < n; ++p)
            P[p] = im.primal[c][size_t(p)];
        for (int r = 0; r < gx.size(); ++r)
            gx[r] = im.dx[c][op.xRows[size_t(r)]];
        for (int r = 0; r < gy.size(); ++r)
            gy[r] = im.dy[c][op.yRows[size_t(r)]];
        out[c] = ldlt.solve(alpha * alpha * P + op.Dx.transpose() * gx + op.Dy.transpose() * gy);
    }
    return out;
}

RgbPlanes eigenReference(const GradientImage& im, double alpha) {
    RgbPlanes out;
    const auto x = referenceSolution(im, alpha);
    for (size_t c = 0; c < 3; ++c)
        out[c].assign(x[c].data(), x[c].data() + x[c].size());
    return out;
}

// Primal and gradients uniform in [-1, 1] (a gradient field that belongs to no image).
GradientImage randomInput(uint32_t w, uint32_t h, Pcg32& rng) {
    GradientImage im;
    im.width = w;
    im.height = h;
    for (auto* planes : {&im.primal, &im.dx, &im.dy})
        for (auto& plane : *planes) {
            plane.resize(im.pixels());
            for (auto& v : plane)
                v = float(2 * rng.nextDouble() - 1);
        }
    return im;
}

} // namespace

TEST_CASE("exact gradients and primal give back the image (L2, L1, every solver)", "[reconstruct]") {
    const uint32_t w = 40, h = 30;
    const RgbPlanes truth = smoothImage(w, h);
    const GradientImage im = exactInput(truth, w, h);
    for (auto norm : {ReconstructNorm::L2, ReconstructNorm::L1})
        for (auto solver : {PoissonSolver::SparseNormalCholesky, PoissonSolver::Cgnr, PoissonSolver::EigenCg,
                            PoissonSolver::Cosine}) {
            INFO("norm " << normName(norm) << ", solver " << int(solver));
            CHECK(maxRelativeError(solve(im, norm, 0.2, solver), truth) < 1e-4);
        }
}

TEST_CASE("the image comes back from exact gradients when the primal only fixes the constant", "[reconstruct]") {
    // Primal = truth + zero-mean noise, alpha = 1e-3: the solution is truth + (alpha^2 + L)^-1 alpha^2 n
    // with L the grid Laplacian; n has no constant component, and L's smallest non-zero eigenvalue on a
    // 16-pixel side is 2 (1 - cos(pi / 16)) = 0.038, so the noise comes through damped by at least
    // 1e-6 / 0.038 = 2.6e-5: about 3e-6 for noise of 0.1, far below 1e-4.
    const uint32_t w = 16, h = 16;
    const RgbPlanes truth = smoothImage(w, h);
    GradientImage im = exactInput(truth, w, h);
    Pcg32 rng(3, 1);
    for (auto& plane : im.primal) {
        std::vector<double> n(plane.size());
        double mean = 0;
        for (auto& v : n) {
            v = 0.1 * standardNormal(rng);
            mean += v / double(n.size());
        }
        for (size_t p = 0; p < plane.size(); ++p)
            plane[p] += float(n[p] - mean);
    }
    CHECK(maxRelativeError(solve(im, ReconstructNorm::L2, 1e-3), truth) < 1e-4);
}

TEST_CASE("Ceres solves the normal equations: same as Eigen's sparse LDL^T on 64x64", "[reconstruct]") {
    const uint32_t w = 64, h = 64;
    GradientImage im = exactInput(smoothImage(w, h), w, h);
    Pcg32 rng(5, 2);
    addNoise(im, rng, 0.3, 0.1);
    for (double alpha : {0.2, 1.0}) {
        const RgbPlanes ref = eigenReference(im, alpha);
        INFO("alpha " << alpha);
        // Sparse Cholesky is exact up to the float output (relative 6e-8).
        CHECK(maxRelativeError(solve(im, ReconstructNorm::L2, alpha, PoissonSolver::SparseNormalCholesky), ref) < 1e-6);
        // CGNR: at alpha 0.2 the condition number is (0.04 + 8) / 0.04 = 201, so 500 CG steps reduce the
        // error by far more than 1e-4.
        CHECK(maxRelativeError(solve(im, ReconstructNorm::L2, alpha, PoissonSolver::Cgnr), ref) < 1e-4);
        // Eigen CG stops at |b - A x| <= tol |b| (tol = kEigenCgTolerance); with |A^-1| = 1 / alpha^2 and
        // |b| <= |A| |x*| = (alpha^2 + 8) |x*| the error is |x - x*| <= tol (alpha^2 + 8) / alpha^2 |x*|.
        const double bound = kEigenCgTolerance * (alpha * alpha + 8) / (alpha * alpha);
        CHECK(relativeNormError(solve(im, ReconstructNorm::L2, alpha, PoissonSolver::EigenCg), ref) < bound);
        // The cosine transform is exact up to rounding, as sparse Cholesky.
        CHECK(maxRelativeError(solve(im, ReconstructNorm::L2, alpha, PoissonSolver::Cosine), ref) < 1e-6);
    }
}

TEST_CASE("the cosine transform solves the L2 normal equations exactly: same as Eigen's sparse LDL^T",
          "[reconstruct]") {
    // Both solves are backward stable, so each one's forward error is bounded by (a small multiple of)
    // kappa eps with eps = 2^-52 and kappa = lambda_max / lambda_min <= (alpha^2 + 8) / alpha^2 the
    // condition number of A = alpha^2 1 + Dx^T Dx + Dy^T Dy (Gershgorin: the Laplacian's eigenvalues lie in
    // [0, 8)). The transform adds a rounding of order eps log2(N) per mode, LDL^T one of order eps times
    // the fill; 64 covers both factors on these sizes. At alpha 1e-4 kappa = 8e8 makes the bound 1.1e-5;
    // at alpha 10, 2e-14. The (0, 0) mode's denominator is alpha^2 = 1e-8 there, exact in the
    // transform's division, so it must not show up as a larger error.
    Pcg32 rng(23, 9);
    for (auto [w, h] :
         {std::pair{7u, 5u}, std::pair{1u, 9u}, std::pair{9u, 1u}, std::pair{1u, 1u}, std::pair{32u, 24u}}) {
        const GradientImage im = randomInput(w, h, rng);
        const CosinePoisson transform(w, h);
        for (double alpha : {1e-4, 0.2, 10.0}) {
            const auto ref = referenceSolution(im, alpha);
            const double kappa = (alpha * alpha + 8) / (alpha * alpha);
            const double bound = 64 * kappa * std::numeric_limits<double>::epsilon();
            for (size_t c = 0; c < 3; ++c) {
                Eigen::VectorXd b;
                normalRightHandSide(im, c, alpha, {}, b);
                Eigen::VectorXd x = b;
                transform.solve({alpha * alpha, 1, 1}, x);
                const double error = (x - ref[c]).norm() / ref[c].norm();
                INFO(w << "x" << h << ", alpha " << alpha << ", channel " << c << ": relative error " << error
                       << ", bound " << bound);
                CHECK(x.allFinite());
                CHECK(error <= bound);
                // The residual of the stencil, as the statistics report it: the same kappa eps bound.
                CHECK(normalResidual(w, h, alpha, {}, b, x) <= bound);
            }
        }
    }
}

TEST_CASE("Eigen CG solves the same problems as Ceres's sparse Cholesky, L2 and L1", "[reconstruct]") {
    const uint32_t w = 48, h = 40;
    GradientImage im = exactInput(smoothImage(w, h), w, h);
    Pcg32 rng(19, 8);
    addNoise(im, rng, 0.3, 0.1);
    for (size_t p = 0; p < im.pixels(); p += 97)
        im.dx[p % 3][p] = 50; // outliers, so that the L1 weights differ strongly from pixel to pixel
    const double alpha = 0.2;
    const file::Buffer exact = solve(im, ReconstructNorm::L2, alpha, PoissonSolver::SparseNormalCholesky);
    const RgbPlanes ref{exact.planes[0], exact.planes[1], exact.planes[2]};
    // The bound on CG's error derived in the test above.
    CHECK(relativeNormError(solve(im, ReconstructNorm::L2, alpha, PoissonSolver::EigenCg), ref) <
          kEigenCgTolerance * (alpha * alpha + 8) / (alpha * alpha));
    // L1: every IRLS step solved to the tolerance (500 CG steps suffice here), so the two reweighting
    // sequences differ only by the CG errors of each step, carried through the weights 1 / (|e| + reg).
    // Those amplify a difference in e by up to 1 / reg: with 5 steps (reg down to 0.05 / 16 = 3e-3) the
    // images stay within the bound of one L2 solve (measured 1.4e-5); with the default 20 (reg 1e-7)
    // they differ by 1.3e-2 where the L1 objective is flat, and the objectives agree to 2.4e-4.
    ReconstructSettings s;
    s.norm = ReconstructNorm::L1;
    s.maxLinearIterations = 500;
    for (int steps : {5, 20}) {
        s.irlsIterations = steps;
        ReconstructStatistics ceresStats, eigenStats;
        s.solver = PoissonSolver::SparseNormalCholesky;
        const file::Buffer a = reconstructScreenedPoisson(im, s, ceresStats);
        s.solver = PoissonSolver::EigenCg;
        const file::Buffer b = reconstructScreenedPoisson(im, s, eigenStats);
        const double e = relativeNormError(b, {a.planes[0], a.planes[1], a.planes[2]});
        INFO(steps << " IRLS steps: relative difference " << e << ", objectives " << ceresStats.finalCost << ", "
                   << eigenStats.finalCost);
        if (steps == 5) CHECK(e < kEigenCgTolerance * (alpha * alpha + 8) / (alpha * alpha));
        CHECK(eigenStats.finalCost == Approx(ceresStats.finalCost).epsilon(1e-3));
    }
}

TEST_CASE("auto: Ceres's sparse Cholesky up to kCholeskyMaxPixels; above, DCT for L2 and Eigen CG for L1",
          "[reconstruct]") {
    ReconstructSettings s;
    ReconstructStatistics stats;
    const RgbPlanes small = smoothImage(64, 64);
    REQUIRE(64 * 64 <= kCholeskyMaxPixels);
    (void)reconstructScreenedPoisson(exactInput(small, 64, 64), s, stats);
    CHECK(stats.solverUsed == PoissonSolver::SparseNormalCholesky);
    CHECK(stats.solver == "SPARSE_NORMAL_CHOLESKY");
    CHECK(stats.solverReason == "auto: 4096 <= 4096 pixels");
    const uint32_t w = 400, h = 300;
    const RgbPlanes truth = smoothImage(w, h);
    const file::Buffer out = reconstructScreenedPoisson(exactInput(truth, w, h), s, stats);
    CHECK(stats.solverUsed == PoissonSolver::Cosine);
    CHECK(stats.solver == "DCT");
    CHECK(stats.solverReason == "auto: 120000 > 4096 pixels, l2");
    CHECK(stats.solves == 3);
    CHECK(stats.linearIterations == 3); // one exact transform solve per channel
    // The residual of an exact solve: rounding only (kappa eps = 201 * 2.2e-16 = 4.5e-14 at alpha 0.2).
    CHECK(stats.linearResidual < 1e-12);
    CHECK(maxRelativeError(out, truth) < 1e-4);
    s.norm = ReconstructNorm::L1;
    s.irlsIterations = 2;
    const RgbPlanes l1Truth = smoothImage(80, 60);
    (void)reconstructScreenedPoisson(exactInput(l1Truth, 80, 60), s, stats);
    CHECK(stats.solverUsed == PoissonSolver::EigenCg);
    CHECK(stats.solver == "EIGEN_CG");
    CHECK(stats.solverReason == "auto: 4800 > 4096 pixels, l1");
}

TEST_CASE("L2 is unbiased: the mean over 1000 noise draws is the truth within 5 standard errors", "[reconstruct]") {
    const uint32_t w = 12, h = 10;
    const double alpha = 0.2, sigmaP = 0.2, sigmaG = 0.05;
    const int draws = 1000;
    const RgbPlanes truth = smoothImage(w, h);
    const int n = int(w * h);
    // The solution is I = A^-1 (alpha^2 P + Dx^T Gx + Dy^T Gy) with A = alpha^2 1 + Dx^T Dx + Dy^T Dy; with
    // independent noise of variances sigmaP^2 on P and sigmaG^2 on G its covariance is
    // A^-1 (alpha^4 sigmaP^2 1 + sigmaG^2 (Dx^T Dx + Dy^T Dy)) A^-1, whose diagonal gives each pixel's
    // standard error sqrt(var / draws).
    const Operators op = differenceOperators(w, h);
    const Eigen::MatrixXd L = Eigen::MatrixXd(op.Dx.transpose() * op.Dx) + Eigen::MatrixXd(op.Dy.transpose() * op.Dy);
    const Eigen::MatrixXd Ainv = (alpha * alpha * Eigen::MatrixXd::Identity(n, n) + L).inverse();
    const Eigen::MatrixXd cov =
        Ainv * (std::pow(alpha, 4) * sigmaP * sigmaP * Eigen::MatrixXd::Identity(n, n) + sigmaG * sigmaG * L) * Ainv;

    RgbPlanes sum;
    for (auto& s : sum)
        s.assign(size_t(n), 0.0f);
    std::array<std::vector<double>, 3> total;
    for (auto& t : total)
        t.assign(size_t(n), 0.0);
    Pcg32 rng(11, 3);
    for (int d = 0; d < draws; ++d) {
        GradientImage im = exactInput(truth, w, h);
        addNoise(im, rng, sigmaP, sigmaG);
        const file::Buffer out = solve(im, ReconstructNorm::L2, alpha);
        for (size_t c = 0; c < 3; ++c)
            for (size_t p = 0; p < size_t(n); ++p)
                total[c][p] += out.planes[c][p];
    }
    double worstZ = 0;
    for (size_t c = 0; c < 3; ++c)
        for (int p = 0; p < n; ++p) {
            const double mean = total[c][size_t(p)] / draws;
            const double standardError = std::sqrt(cov(p, p) / draws);
            worstZ = std::max(worstZ, std::abs(mean - truth[c][size_t(p)]) / standardError);
        }
    // 360 correlated z-scores: the chance that any exceeds 5 is below 360 * 5.7e-7 = 2e-4.
    CHECK(worstZ < 5);
}

TEST_CASE("L1 resists sparse huge gradient outliers that ruin L2", "[reconstruct]") {
    const uint32_t w = 32, h = 32;
    const RgbPlanes truth = smoothImage(w, h);
    GradientImage im = exactInput(truth, w, h);
    Pcg32 rng(7, 4);
    addNoise(im, rng, 0.05, 0.01);
    // 1% of the pixels get a gradient of +-1e6 in all channels (a firefly in a gradient estimate).
    for (size_t p = 0; p < im.pixels(); ++p)
        if (rng.nextDouble() < 0.01) {
            auto& g = rng.nextDouble() < 0.5 ? im.dx : im.dy;
            const float v = rng.nextDouble() < 0.5 ? -1e6f : 1e6f;
            for (auto& plane : g)
                plane[p] = v;
        }
    for (auto solver : {PoissonSolver::Auto, PoissonSolver::Cosine}) {
        const file::Buffer l2 = solve(im, ReconstructNorm::L2, 0.2, solver),
                           l1 = solve(im, ReconstructNorm::L1, 0.2, solver);
        CHECK(allFinite(l1));
        CHECK(allFinite(l2));
        const double e1 = rmse(l1, truth), e2 = rmse(l2, truth);
        INFO("solver " << int(solver) << ": rmse L1 " << e1 << ", L2 " << e2);
        // L2 spreads each 1e6 over its neighbourhood (errors of order 1e4 and more); L1 stays near the
        // noise level of the inputs (0.05 on the primal).
        CHECK(e2 > 1e3);
        CHECK(e1 < 0.1);
    }
}

TEST_CASE("L1 keeps the primal's mean: the energy it takes from a firefly comes back around it", "[reconstruct]") {
    // A firefly in the primal that the gradients do not see (the path's shifts failed): L1 trusts the gradients and
    // its neighbours and drops it, which moves the image mean (screened_poisson.h). The restoration adds back the
    // primal's residual through the kernel S = (beta^2 + D^T D)^-1 beta^2, beta = 1 / meanScale, whose weights sum
    // to one, so the mean comes back exactly; and S is the discrete screened Poisson Green's function, of which a
    // disc of radius r holds 1 - (r beta) K1(r beta) in the continuum: 95 % at r = 4 / beta (K1(4) = 0.01248), so
    // at least 90 % of the removed energy must sit within 4 meanScale of the firefly. Broken on purpose: with the
    // residual added back unsmoothed (S = identity) the disc test passes but the firefly is back whole (the
    // brightest pixel check fails); with it left out (MeanRestoration::Free) the mean is 39 % low and the disc
    // holds nothing.
    const uint32_t w = 64, h = 64;
    const RgbPlanes truth = smoothImage(w, h);
    GradientImage im = exactInput(truth, w, h);
    Pcg32 rng(3, 8);
    addNoise(im, rng, 0.02, 0.005);
    const uint32_t fx = 30, fy = 33;
    const size_t firefly = size_t(fy) * w + fx;
    for (auto& plane : im.primal)
        plane[firefly] += 4000; // about the energy of the whole image (64 x 64 x 1.2)
    double primalSum = 0;
    for (const auto& plane : im.primal)
        for (float v : plane)
            primalSum += v;
    const auto sum = [](const file::Buffer& b) {
        double total = 0;
        for (size_t c = 0; c < 3; ++c)
            for (float v : b.planes[c])
                total += v;
        return total;
    };
    for (auto solver : {PoissonSolver::Auto, PoissonSolver::EigenCg}) {
        ReconstructSettings s;
        s.norm = ReconstructNorm::L1;
        s.solver = solver;
        s.meanScale = 4; // a disc of 4 meanScale well inside the image
        ReconstructStatistics kept, free;
        const file::Buffer k = reconstructScreenedPoisson(im, s, kept);
        s.mean = MeanRestoration::Free;
        const file::Buffer f = reconstructScreenedPoisson(im, s, free);
        INFO("solver " << int(solver) << ": mean shift free " << free.meanShift << ", kept " << kept.meanShift
                       << " (its minimizer " << kept.solveMeanShift << ")");
        CHECK(allFinite(k));
        // The case of the test: L1 alone drops the firefly.
        CHECK(free.meanShift < -0.35);
        CHECK(free.meanShift == Approx(free.solveMeanShift));
        CHECK(kept.solveMeanShift == Approx(free.solveMeanShift).epsilon(1e-6));
        CHECK(free.meanScale == 0);
        CHECK(kept.meanScale == 4);
        // Exact in exact arithmetic, whatever the accuracy of the L1 steps (screened_poisson.h); the float storage of
        // the residual and the output (12288 values, relative rounding 6e-8 each) leaves under 1e-6.
        CHECK(std::abs(kept.meanShift) < 1e-6);
        CHECK(std::abs(sum(k) / primalSum - 1) < 1e-6);
        // Where the energy went: the difference to the free image, within 4 meanScale of the firefly.
        double near = 0, all = 0, brightest = 0;
        for (uint32_t y = 0; y < h; ++y)
            for (uint32_t x = 0; x < w; ++x) {
                const size_t p = size_t(y) * w + x;
                double d = 0;
                for (size_t c = 0; c < 3; ++c)
                    d += double(k.planes[c][p]) - f.planes[c][p];
                all += d;
                if (std::hypot(double(x) - fx, double(y) - fy) <= 4 * s.meanScale) near += d;
                brightest = std::max(brightest, double(k.planes[1][p]));
            }
        INFO("restored " << all << ", within 4 meanScale " << near << "; brightest pixel " << brightest);
        CHECK(near > 0.9 * all);
        // Spread, not put back: the kernel's centre weight is about beta^2 / (4 pi) ln(...) of order 1e-2, so the
        // firefly's pixel keeps a few percent of its 4000.
        CHECK(brightest < 0.1 * 4000);
    }
}

TEST_CASE("a constant offset of the primal shifts the result by that offset", "[reconstruct]") {
    // D (I + c) = D I and alpha (I + c - (P + c)) = alpha (I - P): both objectives, and every IRLS weight,
    // are unchanged by the shift, so the minimizer moves by c.
    const uint32_t w = 20, h = 14;
    GradientImage im = exactInput(smoothImage(w, h), w, h);
    Pcg32 rng(9, 5);
    addNoise(im, rng, 0.2, 0.05);
    GradientImage shifted = im;
    const float offset = 3;
    for (auto& plane : shifted.primal)
        for (auto& v : plane)
            v += offset;
    for (auto norm : {ReconstructNorm::L2, ReconstructNorm::L1}) {
        INFO("norm " << normName(norm));
        const file::Buffer a = solve(im, norm, 0.2), b = solve(shifted, norm, 0.2);
        double worst = 0;
        for (size_t c = 0; c < 3; ++c)
            for (size_t p = 0; p < im.pixels(); ++p)
                worst = std::max(worst, std::abs(double(b.planes[c][p]) - a.planes[c][p] - offset));
        // Float output of values up to 5: rounding 5 * 6e-8 per value; the solves themselves are exact.
        CHECK(worst < 1e-5);
    }
}

TEST_CASE("stiff inputs: alpha 1e-4 .. 10, outliers of 1e6, constant, black, 1x1, 1xN and Nx1 images",
          "[reconstruct]") {
    SECTION("alpha over five decades with outliers: always finite") {
        const uint32_t w = 24, h = 16;
        GradientImage im = exactInput(smoothImage(w, h), w, h);
        im.dx[1][37] = 1e6f;
        im.dy[0][100] = -1e6f;
        for (double alpha : {1e-4, 1e-2, 1.0, 10.0})
            for (auto norm : {ReconstructNorm::L2, ReconstructNorm::L1})
                for (auto solver : {PoissonSolver::Auto, PoissonSolver::Cosine}) {
                    INFO("alpha " << alpha << ", norm " << normName(norm) << ", solver " << int(solver));
                    CHECK(allFinite(solve(im, norm, alpha, solver)));
                }
    }
    SECTION("constant and black images come back exactly") {
        for (float value : {0.0f, 7.5f})
            for (double alpha : {1e-4, 10.0})
                for (auto norm : {ReconstructNorm::L2, ReconstructNorm::L1})
                    for (auto solver : {PoissonSolver::Auto, PoissonSolver::Cosine}) {
                        RgbPlanes flat;
                        for (auto& p : flat)
                            p.assign(9 * 7, value);
                        INFO("value " << value << ", alpha " << alpha << ", norm " << normName(norm) << ", solver "
                                      << int(solver));
                        CHECK(maxRelativeError(solve(exactInput(flat, 9, 7), norm, alpha, solver), flat) < 1e-6);
                    }
    }
    SECTION("degenerate sizes") {
        for (auto [w, h] : {std::pair{1u, 1u}, std::pair{1u, 17u}, std::pair{17u, 1u}})
            for (auto norm : {ReconstructNorm::L2, ReconstructNorm::L1})
                for (auto solver : {PoissonSolver::Auto, PoissonSolver::Cosine}) {
                    INFO(w << "x" << h << ", norm " << normName(norm) << ", solver " << int(solver));
                    const RgbPlanes truth = smoothImage(w, h);
                    CHECK(maxRelativeError(solve(exactInput(truth, w, h), norm, 1e-4, solver), truth) < 1e-4);
                    // 1x1: no difference at all, the result is the primal whatever alpha.
                    GradientImage noisy = exactInput(truth, w, h);
                    Pcg32 rng(w, h);
                    addNoise(noisy, rng, 0.5, 0.5);
                    const file::Buffer out = solve(noisy, norm, 1e-4, solver);
                    CHECK(allFinite(out));
                    if (w * h == 1)
                        for (size_t c = 0; c < 3; ++c)
                            CHECK(out.planes[c][0] == Approx(noisy.primal[c][0]).margin(1e-6));
                }
    }
}

TEST_CASE("the direct plane stays out of the solve and is added back", "[reconstruct]") {
    const uint32_t w = 10, h = 8;
    GradientImage im = exactInput(smoothImage(w, h), w, h);
    Pcg32 rng(13, 6);
    addNoise(im, rng, 0.2, 0.05);
    const file::Buffer without = solve(im, ReconstructNorm::L2, 0.2);
    RgbPlanes direct;
    for (auto& plane : direct) {
        plane.resize(im.pixels());
        for (auto& v : plane)
            v = rng.nextDouble() < 0.1 ? 50.0f : 0.0f; // a few bright emitter pixels
    }
    im.direct = direct;
    const file::Buffer with = solve(im, ReconstructNorm::L2, 0.2);
    for (size_t c = 0; c < 3; ++c)
        for (size_t p = 0; p < im.pixels(); ++p)
            CHECK(with.planes[c][p] == Approx(without.planes[c][p] + direct[c][p]).margin(1e-5));
}

TEST_CASE("statistics of a reconstruction", "[reconstruct]") {
    const uint32_t w = 12, h = 9;
    GradientImage im = exactInput(smoothImage(w, h), w, h);
    Pcg32 rng(17, 7);
    addNoise(im, rng, 0.2, 0.05);
    ReconstructSettings s;
    ReconstructStatistics stats;
    (void)reconstructScreenedPoisson(im, s, stats);
    CHECK(stats.norm == "l2");
    CHECK(stats.solves == 3);
    CHECK(stats.solverIterations == 3); // one Gauss-Newton step per channel solves a linear problem
    CHECK(stats.irlsIterations == 0);
    CHECK(stats.solver == "SPARSE_NORMAL_CHOLESKY");
    CHECK(stats.finalCost < stats.initialCost);
    s.norm = ReconstructNorm::L1;
    s.irlsIterations = 5;
    (void)reconstructScreenedPoisson(im, s, stats);
    CHECK(stats.norm == "l1");
    CHECK(stats.irlsIterations == 5);
    CHECK(stats.solves == 3 * 5); // one per reweighting step (from the primal)
    CHECK(stats.meanScale == kMeanScale);
    CHECK(stats.meanSolves == 3); // the mean's restoration, one L2 solve per channel
    CHECK(stats.meanSolver == "SPARSE_NORMAL_CHOLESKY");
    CHECK(stats.finalCost < stats.initialCost);
    // DCT: capped, transform-preconditioned CG for each reweighting step; one exact solve per channel for L2.
    s.solver = PoissonSolver::Cosine;
    (void)reconstructScreenedPoisson(im, s, stats);
    CHECK(stats.solver == "DCT");
    CHECK(stats.solverReason == "requested");
    CHECK(stats.solves == 3 * 5);
    CHECK(stats.solverIterations == 3 * 5);
    CHECK(stats.linearIterations > 0);
    CHECK(stats.linearIterations <= 3 * 5 * kCosineL1Iterations);
    CHECK(stats.meanSolver == "SPARSE_NORMAL_CHOLESKY"); // auto's exact solver at 12 x 9, not the one requested
    CHECK(stats.linearResidual > 0);
    CHECK(stats.finalCost < stats.initialCost);
    s.norm = ReconstructNorm::L2;
    (void)reconstructScreenedPoisson(im, s, stats);
    CHECK(stats.solves == 3);
    CHECK(stats.solverIterations == 3);
    CHECK(stats.linearIterations == 3);
    CHECK(stats.linearResidual < 1e-12); // exact up to rounding (kappa eps = 201 * 2.2e-16 at alpha 0.2)
    CHECK(stats.finalCost < stats.initialCost);
}

TEST_CASE("bad input and settings: one message naming the file and the problem", "[reconstruct]") {
    const uint32_t w = 4, h = 3;
    const RgbPlanes truth = smoothImage(w, h);
    file::Buffer b;
    b.width = w;
    b.height = h;
    const char* rgb[3] = {"R", "G", "B"};
    for (const char* layer : {"primal", "dx", "dy"})
        for (size_t c = 0; c < 3; ++c) {
            b.channels.push_back(std::string(layer) + "." + rgb[c]);
            b.planes.push_back(truth[c]);
        }
    CHECK_NOTHROW(gradientImageFromBuffer(b, "in.lts"));
    CHECK_FALSE(gradientImageFromBuffer(b, "in.lts").direct.has_value());

    file::Buffer nan = b;
    nan.planes[4][5] = std::numeric_limits<float>::quiet_NaN(); // dx.G at (1, 1)
    CHECK(test::errorOf([&] { (void)gradientImageFromBuffer(nan, "in.lts"); }) ==
          "in.lts: channel dx.G is NaN at pixel (1, 1)");
    file::Buffer inf = b;
    inf.planes[8][11] = std::numeric_limits<float>::infinity();
    CHECK(test::errorOf([&] { (void)gradientImageFromBuffer(inf, "in.lts"); }) ==
          "in.lts: channel dy.B is infinite at pixel (3, 2)");

    file::Buffer missing = b;
    missing.channels.resize(6);
    missing.planes.resize(6);
    CHECK(test::errorOf([&] { (void)gradientImageFromBuffer(missing, "in.exr"); }) ==
          "in.exr: no layer 'dy' (channels dy.R/G/B); it has primal.R, primal.G, primal.B, dx.R, dx.G, dx.B");
    file::Buffer partial = b;
    partial.channels.push_back("direct.R");
    partial.planes.push_back(truth[0]);
    CHECK(test::errorOf([&] { (void)gradientImageFromBuffer(partial, "in.lts"); }) ==
          "in.lts: layer 'direct' is incomplete: no channel direct.G, direct.B");

    // Separate files: plain R, G, B per file; a size mismatch names the file that differs.
    const file::Buffer p = rgbBuffer(w, h, truth), small = rgbBuffer(2, 2, smoothImage(2, 2));
    CHECK_NOTHROW(gradientImageFromLayers({&p, "p.exr"}, {&p, "dx.exr"}, {&p, "dy.exr"}, std::nullopt));
    CHECK(test::errorOf([&] {
              (void)gradientImageFromLayers({&p, "p.exr"}, {&small, "dx.exr"}, {&p, "dy.exr"}, std::nullopt);
          }) == "dx.exr: 2x2 does not match the primal p.exr (4x3)");

    const GradientImage im = gradientImageFromBuffer(b, "in.lts");
    ReconstructStatistics stats;
    for (double alpha : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN()}) {
        ReconstructSettings s;
        s.alpha = alpha;
        CHECK_THROWS_AS(reconstructScreenedPoisson(im, s, stats), Error);
    }
}
