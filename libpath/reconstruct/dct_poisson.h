// The screened Poisson equation with constant coefficients on the pixel grid, solved exactly by the
// discrete cosine transform (the normal equations of Bauszat et al. 2017, Sec. 2.2, with all weights 1):
//   (s 1 + a_x Dx^T Dx + a_y Dy^T Dy) v = b,
// Dx, Dy the forward differences of gradient_image.h, without the difference that would leave the image.
// Dx^T Dx is, in every row, the Laplacian of a path graph of W vertices (Neumann boundary), whose
// eigenvectors are the DCT-II basis cos(pi k (x + 1/2) / W) with eigenvalues 2 - 2 cos(pi k / W); Dy^T Dy
// likewise in every column. The 2-D DCT-II therefore diagonalizes the whole operator: transform b,
// divide mode (k, l) by s + a_x lambda_x(k) + a_y lambda_y(l), transform back (DCT-III), O(N log N) and
// exact up to rounding. With L2's weights (s = alpha^2, a_x = a_y = 1) this is the L2 reconstruction
// itself; with L1's per-pixel IRLS weights it is the core of a preconditioner of conjugate gradients
// (CosinePreconditioner below).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "reconstruct/normal_equations.h"

namespace lt {

// The constant-coefficient operator s 1 + a_x Dx^T Dx + a_y Dy^T Dy; every coefficient > 0 keeps it
// positive definite (s > 0 is what pins the constant, the (0, 0) mode).
struct ScreenedLaplacian {
    double screen = 1;   // s: alpha^2 times the primal residuals' weight
    double x = 1, y = 1; // a_x, a_y: the weights of the dx and dy residuals
};

// FFTW plans of the forward (DCT-II) and inverse (DCT-III) 2-D transforms of one image size. Planning
// is FFTW_ESTIMATE: FFTW_MEASURE made the transforms of 1280x720 35% faster (36 instead of 56 ms for
// the pair) but took 2.2 s to plan, longer than a whole L2 reconstruction. Solves may run concurrently
// (one per channel): FFTW's execute functions are thread-safe, its planner is not and is serialized here.
class CosinePoisson {
public:
    CosinePoisson(uint32_t width, uint32_t height);
    ~CosinePoisson();
    CosinePoisson(const CosinePoisson&) = delete;
    CosinePoisson& operator=(const CosinePoisson&) = delete;

    // Solves op v = b in place: v holds b (width * height values, row-major) on entry and v on exit.
    void solve(const ScreenedLaplacian& op, Eigen::Ref<Eigen::VectorXd> v) const;

    [[nodiscard]] size_t pixels() const { return size_t(width_) * height_; }

private:
    struct Plans;
    uint32_t width_, height_;
    std::unique_ptr<Plans> plans_;
    std::vector<double> lambdaX_, lambdaY_; // eigenvalues of the 1-D path Laplacians, per column / row mode
};

// Preconditioner of Eigen's ConjugateGradient for the weighted normal matrix A of L1's IRLS steps:
// M = S L0 S, L0 a ScreenedLaplacian (one weight per term) and S = diag(sqrt(A_pp / L0_pp)) the scaling
// that gives M the diagonal of A, so M^-1 r = S^-1 L0^-1 S^-1 r is one exact cosine-transform solve
// between two scalings (L0_pp is taken at an interior pixel, s + 2 a_x + 2 a_y; at the border M's
// diagonal is then a little smaller than A's, still an SPD preconditioner). Eigen default-constructs it
// inside the solver; set(...) gives it the transform, L0 and 1 / S before the solve.
class CosinePreconditioner {
public:
    using StorageIndex = int;
    enum { ColsAtCompileTime = Eigen::Dynamic, MaxColsAtCompileTime = Eigen::Dynamic };

    void set(const CosinePoisson& transform, const ScreenedLaplacian& op, Eigen::VectorXd inverseScale) {
        transform_ = &transform;
        op_ = op;
        inverseScale_ = std::move(inverseScale);
    }

    // Eigen's interface: nothing to factor, the transform is the factorization.
    template <typename Matrix> CosinePreconditioner& analyzePattern(const Matrix&) { return *this; }
    template <typename Matrix> CosinePreconditioner& factorize(const Matrix&) { return *this; }
    template <typename Matrix> CosinePreconditioner& compute(const Matrix&) { return *this; }
    [[nodiscard]] Eigen::ComputationInfo info() const { return Eigen::Success; }
    [[nodiscard]] Eigen::VectorXd solve(const Eigen::VectorXd& r) const {
        Eigen::VectorXd z = r.cwiseProduct(inverseScale_);
        transform_->solve(op_, z);
        return z.cwiseProduct(inverseScale_);
    }

private:
    const CosinePoisson* transform_ = nullptr;
    ScreenedLaplacian op_;
    Eigen::VectorXd inverseScale_;
};

// L0 for the weighted normal equations of `weights` (normal_equations.h) of a width x height image: each
// term's weight replaced by its harmonic mean over the residuals that exist, i.e. by 1 / mean(|e| + reg)
// for IRLS weights 1 / (|e| + reg). Empty weights (L2) give the unweighted operator itself.
[[nodiscard]] ScreenedLaplacian harmonicWeightOperator(double alpha, const ResidualWeights& weights, uint32_t width,
                                                       uint32_t height);

// Solves A x = b by conjugate gradients preconditioned with CosinePreconditioner (L0 = `op`), from x (the
// warm start), until |b - A x| <= tolerance |b| or maxIterations steps (as solveNormalEquations).
ConjugateGradientResult solveNormalEquationsCosine(const NormalMatrix& A, const Eigen::VectorXd& b,
                                                   const CosinePoisson& transform, const ScreenedLaplacian& op,
                                                   double tolerance, int maxIterations, Eigen::Ref<Eigen::VectorXd> x);

} // namespace lt
