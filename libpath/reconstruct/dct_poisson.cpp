#include "reconstruct/dct_poisson.h"

#include <fftw3.h>

#include <cmath>
#include <mutex>
#include <string>
#include <type_traits>

#include "math/constants.h"
#include "util/error.h"

namespace lt {

namespace {

// FFTW's planner (and fftw_destroy_plan) keep global state; only fftw_execute* may run concurrently.
std::mutex& plannerMutex() {
    static std::mutex m;
    return m;
}

struct PlanDeleter {
    void operator()(fftw_plan p) const {
        const std::lock_guard lock(plannerMutex());
        fftw_destroy_plan(p);
    }
};
using Plan = std::unique_ptr<std::remove_pointer_t<fftw_plan>, PlanDeleter>;

// Eigenvalues 2 - 2 cos(pi k / n) of the path-graph Laplacian of n vertices (the 1-D Dx^T Dx).
std::vector<double> pathLaplacianEigenvalues(uint32_t n) {
    std::vector<double> lambda(n);
    for (uint32_t k = 0; k < n; ++k)
        lambda[k] = 2 - 2 * std::cos(Pi * double(k) / double(n));
    return lambda;
}

} // namespace

struct CosinePoisson::Plans {
    Plan forward, inverse;
};

CosinePoisson::CosinePoisson(uint32_t width, uint32_t height)
    : width_(width), height_(height), plans_(std::make_unique<Plans>()), lambdaX_(pathLaplacianEigenvalues(width)),
      lambdaY_(pathLaplacianEigenvalues(height)) {
    // FFTW_ESTIMATE leaves the planning array untouched; FFTW_UNALIGNED lets the plans run on any
    // caller's array (an Eigen or std::vector buffer need not have the planning array's SIMD alignment;
    // measured at 1280x720: no slower than aligned plans).
    const unsigned flags = FFTW_ESTIMATE | FFTW_UNALIGNED;
    const std::unique_ptr<double, decltype(&fftw_free)> scratch(fftw_alloc_real(pixels()), &fftw_free);
    if (!scratch) throw Error("reconstruction: out of memory for the cosine transform");
    const std::lock_guard lock(plannerMutex());
    // Row-major: height rows (FFTW's first dimension) of width values.
    plans_->forward.reset(
        fftw_plan_r2r_2d(int(height), int(width), scratch.get(), scratch.get(), FFTW_REDFT10, FFTW_REDFT10, flags));
    plans_->inverse.reset(
        fftw_plan_r2r_2d(int(height), int(width), scratch.get(), scratch.get(), FFTW_REDFT01, FFTW_REDFT01, flags));
    if (!plans_->forward || !plans_->inverse)
        throw Error("reconstruction: FFTW could not plan the " + std::to_string(width) + "x" + std::to_string(height) +
                    " cosine transform");
}

CosinePoisson::~CosinePoisson() = default;

void CosinePoisson::solve(const ScreenedLaplacian& op, Eigen::Ref<Eigen::VectorXd> v) const {
    double* data = v.data();
    fftw_execute_r2r(plans_->forward.get(), data, data);
    // FFTW's DCT-II followed by its DCT-III multiplies by 2n per dimension; the division folds that in.
    // Every denominator is at least op.screen > 0 (lambda >= 0), so no mode divides by zero; the (0, 0)
    // mode, the image's mean, gets exactly 1 / op.screen (1e8 for alpha = 1e-4), which is the true
    // operator's response to a constant: no rounding is amplified beyond what the equation itself does.
    const double scale = 4.0 * double(width_) * double(height_);
    for (uint32_t l = 0; l < height_; ++l) {
        const double rowTerm = op.screen + op.y * lambdaY_[l];
        double* row = data + size_t(l) * width_;
        for (uint32_t k = 0; k < width_; ++k)
            row[k] /= scale * (rowTerm + op.x * lambdaX_[k]);
    }
    fftw_execute_r2r(plans_->inverse.get(), data, data);
}

ScreenedLaplacian harmonicWeightOperator(double alpha, const ResidualWeights& weights, uint32_t width,
                                         uint32_t height) {
    ScreenedLaplacian op;
    op.screen = alpha * alpha;
    if (weights.primal.empty()) return op;
    // Sums of 1 / w (w the square of the stored square root) over the residuals that exist: the last
    // column has no dx residual, the last row no dy residual.
    double primal = 0, x = 0, y = 0;
    for (uint32_t py = 0; py < height; ++py)
        for (uint32_t px = 0; px < width; ++px) {
            const size_t p = size_t(py) * width + px;
            primal += 1 / (double(weights.primal[p]) * weights.primal[p]);
            if (px + 1 < width) x += 1 / (double(weights.dx[p]) * weights.dx[p]);
            if (py + 1 < height) y += 1 / (double(weights.dy[p]) * weights.dy[p]);
        }
    op.screen *= double(width) * height / primal;
    // A 1-pixel-wide image has no dx residual: any positive a_x gives the same (lambda_x = 0) operator.
    op.x = width > 1 ? double(width - 1) * height / x : 1;
    op.y = height > 1 ? double(height - 1) * width / y : 1;
    return op;
}

ConjugateGradientResult solveNormalEquationsCosine(const NormalMatrix& A, const Eigen::VectorXd& b,
                                                   const CosinePoisson& transform, const ScreenedLaplacian& op,
                                                   double tolerance, int maxIterations, Eigen::Ref<Eigen::VectorXd> x) {
    const double interiorDiagonal = op.screen + 2 * op.x + 2 * op.y;
    return conjugateGradients<CosinePreconditioner>(A, b, tolerance, maxIterations, x, [&](CosinePreconditioner& p) {
        p.set(transform, op, (interiorDiagonal / A.diagonal().array()).sqrt().matrix());
    });
}

} // namespace lt
