// The normal equations of the weighted screened Poisson problem on the pixel grid,
//   (alpha^2 W_p + Dx^T W_x Dx + Dy^T W_y Dy) I = alpha^2 W_p P + Dx^T W_x Gx + Dy^T W_y Gy,
// assembled straight from the 5-point stencil as an Eigen sparse matrix and solved by Eigen's conjugate
// gradients: the backend of reconstructScreenedPoisson for images too large for Ceres (screened_poisson.cpp);
// the right-hand side and residual also serve the cosine-transform solver (dct_poisson.h).
// W are the IRLS weights of L1 (per pixel, shared by R, G and B); all 1 for L2.
#pragma once

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/Sparse>
#include <vector>

#include "reconstruct/gradient_image.h"

namespace lt {

// Square roots of the IRLS weights of each pixel's primal, dx and dy residuals (the factor Ceres puts on
// a residual). Empty vectors: all weights 1 (L2).
struct ResidualWeights {
    std::vector<float> primal, dx, dy;
};

// Row-major with both triangles stored: Eigen's CG then uses a plain sparse mat-vec, the fastest product.
// 5 entries per row (fewer at the border): 64 bytes per pixel with 32-bit indices.
using NormalMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;

// The matrix of the normal equations of an image of width x height pixels. The pattern depends on the
// size only, so reassembling with new weights (each IRLS step) rewrites the same arrays.
void assembleNormalMatrix(uint32_t width, uint32_t height, double alpha, const ResidualWeights& weights,
                          NormalMatrix& A);

// The right-hand side of the normal equations for channel c (0, 1, 2 = R, G, B).
void normalRightHandSide(const GradientImage& image, size_t c, double alpha, const ResidualWeights& weights,
                         Eigen::VectorXd& b);

// |b - A x| / |b| for the normal matrix A of assembleNormalMatrix, computed from its stencil without
// assembling it (|b - A x| when b = 0): the accuracy of a solve that never formed A (dct_poisson.h).
[[nodiscard]] double normalResidual(uint32_t width, uint32_t height, double alpha, const ResidualWeights& weights,
                                    const Eigen::VectorXd& b, const Eigen::Ref<const Eigen::VectorXd>& x);

struct ConjugateGradientResult {
    int iterations = 0;
    double relativeResidual = 0; // |b - A x| / |b| at exit
};

// Solves A x = b by conjugate gradients with the preconditioner P (Eigen's preconditioner interface)
// starting from x (the warm start), until |b - A x| <= tolerance |b| or maxIterations steps; leaves the
// result in x. `prepare(P&)` sets the preconditioner up before the solve (Eigen default-constructs it).
template <class Preconditioner, class Prepare>
ConjugateGradientResult conjugateGradients(const NormalMatrix& A, const Eigen::VectorXd& b, double tolerance,
                                           int maxIterations, Eigen::Ref<Eigen::VectorXd> x, Prepare&& prepare) {
    Eigen::ConjugateGradient<NormalMatrix, Eigen::Lower | Eigen::Upper, Preconditioner> cg;
    prepare(cg.preconditioner());
    cg.setTolerance(tolerance);
    cg.setMaxIterations(maxIterations);
    cg.compute(A);
    // x is the guess and the result: Eigen copies the guess into the destination first, a no-op here.
    x = cg.solveWithGuess(b, x);
    return {int(cg.iterations()), cg.error()};
}

// Conjugate gradients with the Jacobi preconditioner (Eigen CG).
inline ConjugateGradientResult solveNormalEquations(const NormalMatrix& A, const Eigen::VectorXd& b, double tolerance,
                                                    int maxIterations, Eigen::Ref<Eigen::VectorXd> x) {
    return conjugateGradients<Eigen::DiagonalPreconditioner<double>>(A, b, tolerance, maxIterations, x,
                                                                     [](auto&) {});
}

} // namespace lt
