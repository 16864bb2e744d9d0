#include "reconstruct/screened_poisson.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <cmath>
#include <memory>
#include <optional>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include "util/error.h"
#include "reconstruct/dct_poisson.h"
#include "reconstruct/normal_equations.h"

namespace lt {

namespace {

// What the per-pixel cost functions read when Ceres evaluates them: the channel being solved and the
// IRLS weights. One Problem serves the three channels and every reweighting step, only this changes,
// so the (costly) construction of millions of residual blocks happens once per reconstruction.
struct SolveData {
    uint32_t width = 0;
    double alpha = 0;
    const float* primal = nullptr;
    const float* dx = nullptr;
    const float* dy = nullptr;
    // Square roots of the IRLS weights of the primal, dx and dy residuals of each pixel (a
    // weighted least-squares residual is sqrt(w) r); null for L2, where all weights are 1.
    const float* sqrtWeightPrimal = nullptr;
    const float* sqrtWeightDx = nullptr;
    const float* sqrtWeightDy = nullptr;
};

// Ceres's cost is per residual and parameter block (its bookkeeping, and in CGNR one small dense
// matrix product per Jacobian cell): with one parameter block per pixel a 1280x720 L2 solve took 1.1 GB
// and 37 s. Parameter blocks are therefore row segments of up to kSegment pixels (rows are cut at the same columns,
// so a segment's lower neighbour covers the same columns), and three kinds of residual blocks:
//   Segment:  alpha (I_p - P_p) for its pixels, then (I_{p+1} - I_p) - Gx_p inside it;  block {s}
//   Cross:    (I_{p+1} - I_p) - Gx_p from its last pixel to the next segment's first;  blocks {s, right}
//   Vertical: (I_{p+W} - I_p) - Gy_p for its pixels;                                   blocks {s, below}
// Every residual is multiplied by its pixel's sqrt(IRLS weight). The Jacobian is constant (the problem
// is linear), so Ceres's Gauss-Newton step is the exact minimizer. Segments of 4 gave 0.88 GB and 31 s
// at 1280x720 (2: 1.1 GB, 29 s; 8: 0.90 GB, 39 s, the padding of the dense cells costing more than
// the fewer blocks save).
constexpr uint32_t kSegment = 4;

class SegmentCost final : public ceres::CostFunction {
public:
    enum class Kind { Segment, Cross, Vertical };

    // `first`: the segment's first pixel; `n` its length; `nextLength` the length of the right
    // neighbour (Cross only).
    SegmentCost(const SolveData& data, Kind kind, size_t first, int n, int nextLength = 0)
        : data_(data), kind_(kind), first_(first), n_(n) {
        auto& sizes = *mutable_parameter_block_sizes();
        switch (kind) {
        case Kind::Segment:
            set_num_residuals(2 * n - 1);
            sizes = {n};
            break;
        case Kind::Cross:
            set_num_residuals(1);
            sizes = {n, nextLength};
            break;
        case Kind::Vertical:
            set_num_residuals(n);
            sizes = {n, n};
            break;
        }
    }

    bool Evaluate(double const* const* x, double* residuals, double** jacobians) const override {
        const SolveData& d = data_;
        const int n = n_;
        const auto weight = [](const float* w, size_t p) { return w ? double(w[p]) : 1.0; };
        switch (kind_) {
        case Kind::Segment: {
            double* J = jacobians && jacobians[0] ? jacobians[0] : nullptr;
            if (J) std::fill(J, J + (2 * n - 1) * n, 0.0);
            for (int i = 0; i < n; ++i) {
                const size_t p = first_ + size_t(i);
                const double s = weight(d.sqrtWeightPrimal, p) * d.alpha;
                residuals[i] = s * (x[0][i] - d.primal[p]);
                if (J) J[i * n + i] = s;
            }
            for (int i = 0; i + 1 < n; ++i) {
                const size_t p = first_ + size_t(i);
                const double s = weight(d.sqrtWeightDx, p);
                residuals[n + i] = s * (x[0][i + 1] - x[0][i] - d.dx[p]);
                if (J) {
                    J[(n + i) * n + i] = -s;
                    J[(n + i) * n + i + 1] = s;
                }
            }
            break;
        }
        case Kind::Cross: {
            const size_t p = first_ + size_t(n - 1);
            const double s = weight(d.sqrtWeightDx, p);
            residuals[0] = s * (x[1][0] - x[0][n - 1] - d.dx[p]);
            if (jacobians && jacobians[0]) {
                std::fill(jacobians[0], jacobians[0] + n, 0.0);
                jacobians[0][n - 1] = -s;
            }
            if (jacobians && jacobians[1]) {
                std::fill(jacobians[1], jacobians[1] + parameter_block_sizes()[1], 0.0);
                jacobians[1][0] = s;
            }
            break;
        }
        case Kind::Vertical: {
            for (int b = 0; b < 2; ++b)
                if (jacobians && jacobians[b]) std::fill(jacobians[b], jacobians[b] + n * n, 0.0);
            for (int i = 0; i < n; ++i) {
                const size_t p = first_ + size_t(i);
                const double s = weight(d.sqrtWeightDy, p);
                residuals[i] = s * (x[1][i] - x[0][i] - d.dy[p]);
                if (jacobians && jacobians[0]) jacobians[0][i * n + i] = -s;
                if (jacobians && jacobians[1]) jacobians[1][i * n + i] = s;
            }
            break;
        }
        }
        return true;
    }

private:
    const SolveData& data_;
    Kind kind_;
    size_t first_;
    int n_;
};

using Solution = std::array<std::vector<double>, 3>;

// The squared RGB norms of pixel p's three residuals at `x`: primal (alpha (x - P)), and the forward
// differences against dx and dy (zero where the difference would leave the image).
struct PixelResiduals {
    double primal = 0, dx = 0, dy = 0;
};
PixelResiduals pixelResiduals(const GradientImage& im, const Solution& x, double alpha, uint32_t px, uint32_t y) {
    const uint32_t W = im.width, H = im.height;
    const size_t p = size_t(y) * W + px;
    PixelResiduals e;
    for (size_t c = 0; c < 3; ++c) {
        const double rp = alpha * (x[c][p] - im.primal[c][p]);
        e.primal += rp * rp;
        if (px + 1 < W) {
            const double r = x[c][p + 1] - x[c][p] - im.dx[c][p];
            e.dx += r * r;
        }
        if (y + 1 < H) {
            const double r = x[c][p + W] - x[c][p] - im.dy[c][p];
            e.dy += r * r;
        }
    }
    return e;
}

// The objective of screened_poisson.h for the chosen norm at `x` (per-pixel RGB norms for L1).
double objective(const GradientImage& im, const Solution& x, double alpha, ReconstructNorm norm) {
    double total = 0;
    for (uint32_t y = 0; y < im.height; ++y)
        for (uint32_t px = 0; px < im.width; ++px) {
            const PixelResiduals e = pixelResiduals(im, x, alpha, px, y);
            total += norm == ReconstructNorm::L2 ? e.primal + e.dx + e.dy
                                                 : std::sqrt(e.primal) + std::sqrt(e.dx) + std::sqrt(e.dy);
        }
    return total;
}

// IRLS weights for the L1 objective at `x`: w = 1 / (|e|_2 + reg) per pixel and
// residual, from the RGB vector norm |e|_2, so the three channels share one weight and stay one
// problem each. Minimizing sum w |e|^2 with these weights is the majorizer of sum |e| at x.
void irlsWeights(const GradientImage& im, const Solution& x, double alpha, double reg, ResidualWeights& weights) {
    weights.primal.resize(im.pixels());
    weights.dx.resize(im.pixels());
    weights.dy.resize(im.pixels());
    for (uint32_t y = 0; y < im.height; ++y)
        for (uint32_t px = 0; px < im.width; ++px) {
            const size_t p = size_t(y) * im.width + px;
            const PixelResiduals e = pixelResiduals(im, x, alpha, px, y);
            weights.primal[p] = float(1 / std::sqrt(std::sqrt(e.primal) + reg));
            weights.dx[p] = float(1 / std::sqrt(std::sqrt(e.dx) + reg));
            weights.dy[p] = float(1 / std::sqrt(std::sqrt(e.dy) + reg));
        }
}

// One Ceres problem over the pixels of one channel, re-targeted at a channel and weights per solve.
class ChannelProblem {
public:
    ChannelProblem(const GradientImage& im, double alpha) : image_(im), values_(im.pixels()) {
        data_.width = im.width;
        data_.alpha = alpha;
        ceres::Problem::Options options;
        // Every block is added exactly once below; the checks for repeated or aliased blocks cost a
        // lookup per block.
        options.disable_all_safety_checks = true;
        problem_ = std::make_unique<ceres::Problem>(options);
        const uint32_t W = im.width, H = im.height;
        // Parameter blocks in scan order, so the Jacobian's columns are too.
        for (uint32_t y = 0; y < H; ++y)
            for (uint32_t x = 0; x < W; x += kSegment)
                problem_->AddParameterBlock(&values_[size_t(y) * W + x], int(std::min(kSegment, W - x)));
        using Kind = SegmentCost::Kind;
        for (uint32_t y = 0; y < H; ++y)
            for (uint32_t x = 0; x < W; x += kSegment) {
                const size_t p = size_t(y) * W + x;
                const int n = int(std::min(kSegment, W - x));
                double* here = &values_[p];
                problem_->AddResidualBlock(new SegmentCost(data_, Kind::Segment, p, n), nullptr, here);
                if (x + kSegment < W) {
                    const int next = int(std::min(kSegment, W - x - kSegment));
                    problem_->AddResidualBlock(new SegmentCost(data_, Kind::Cross, p, n, next), nullptr, here,
                                               &values_[p + size_t(n)]);
                }
                if (y + 1 < H)
                    problem_->AddResidualBlock(new SegmentCost(data_, Kind::Vertical, p, n), nullptr, here,
                                               &values_[p + W]);
            }
    }

    // The weights must outlive the solves; empty ones (L2) weigh every residual 1.
    void setWeights(const ResidualWeights& w) {
        data_.sqrtWeightPrimal = w.primal.empty() ? nullptr : w.primal.data();
        data_.sqrtWeightDx = w.dx.empty() ? nullptr : w.dx.data();
        data_.sqrtWeightDy = w.dy.empty() ? nullptr : w.dy.data();
    }

    // Solves channel c starting from x[c] (the warm start) and leaves the result there.
    ceres::Solver::Summary solve(size_t c, std::vector<double>& x, const ceres::Solver::Options& options) {
        data_.primal = image_.primal[c].data();
        data_.dx = image_.dx[c].data();
        data_.dy = image_.dy[c].data();
        values_ = x;
        ceres::Solver::Summary summary;
        ceres::Solve(options, problem_.get(), &summary);
        if (summary.termination_type == ceres::FAILURE || summary.termination_type == ceres::USER_FAILURE)
            throw Error("reconstruction: Ceres failed: " + summary.message);
        x = values_;
        return summary;
    }

private:
    const GradientImage& image_;
    SolveData data_;
    std::vector<double> values_; // the parameter blocks
    std::unique_ptr<ceres::Problem> problem_;
};

void checkSettings(const ReconstructSettings& s) {
    if (!(s.alpha > 0) || !std::isfinite(s.alpha))
        throw Error("alpha must be positive and finite, got " + std::to_string(s.alpha));
    if (s.irlsIterations < 1) throw Error("IRLS iterations must be at least 1");
    if (!(s.irlsRegularizer > 0) || !std::isfinite(s.irlsRegularizer))
        throw Error("the IRLS regularizer must be positive and finite, got " + std::to_string(s.irlsRegularizer));
    if (!(s.irlsDecay > 0 && s.irlsDecay <= 1))
        throw Error("the IRLS decay must be in (0, 1], got " + std::to_string(s.irlsDecay));
    if (s.maxLinearIterations < 0) throw Error("the linear solver iterations must not be negative");
    if (s.threads < 1) throw Error("threads must be at least 1");
    if (!(s.meanScale > 0) || !std::isfinite(s.meanScale))
        throw Error("the mean's scale must be positive and finite, got " + std::to_string(s.meanScale));
}

// The solver a reconstruction uses, with the reason in `statistics`.
//
// The design card names Ceres, and it stays the solver of small images: exact, and its Problem is
// checked against an independent solve. For large ones its cost is the obstacle, not the method: at
// 1280x720 RGB (pipelines/bench/reconstruct.sh, 2 cores) Ceres CGNR took 36-39 s for L2 and 419-685 s
// for L1 at 0.95 KB per pixel, half of it in Ceres's block-sparse products (100-200 ms per CG step,
// single-threaded in Ceres 2.1) and 0.6-1 s of problem setup per solve. Eigen CG on the assembled
// 5-point matrix of the same normal equations: 18 ms per CG step (memory-bound: 64 bytes of matrix
// and ~19 vector passes per pixel), 2.8 s of solve for L2 on 2 threads, 9-15 s for L1 (depending on
// the load of the shared machine), 0.3 GB; 4K L2 30 s, 1.9 GB. Ceres's sparse Cholesky,
// 2 threads, L2 / L1: 0.07 / 1.3 s at 64x64, 0.34 / 7.4 s at 128x128, 2.4 / 45 s at 256x256
// (Eigen CG: 0.01 / 0.03, 0.04 / 0.10, 0.13 / 0.5 s), hence the threshold kCholeskyMaxPixels.
// Above it L2 goes to the cosine transform (dct_poisson.h): exact (relative residual ~1e-15) and
// O(N log N), 0.16-0.32 s of solve at 1280x720 on 2 threads (Eigen CG: 2.8-4.3 s to 1e-5), 0.2 GB,
// the whole bench run about 1 s; 4K 2.5 s of solve, 0.7 GB. L1 stays with Eigen CG: its IRLS
// weights change per pixel and by up to 1 / reg (1e7 at the last step), which no transform
// diagonalizes, and the transform-preconditioned CG measured no faster (kCosineL1Iterations).
PoissonSolver chooseSolver(const ReconstructSettings& settings, size_t N, ReconstructStatistics& statistics) {
    if (settings.solver != PoissonSolver::Auto) {
        statistics.solverReason = "requested";
        return settings.solver;
    }
    const bool small = N <= kCholeskyMaxPixels;
    const bool l1 = settings.norm == ReconstructNorm::L1;
    statistics.solverReason = "auto: " + std::to_string(N) + (small ? " <= " : " > ") +
                              std::to_string(kCholeskyMaxPixels) + " pixels" +
                              (small ? "" : ", " + normName(settings.norm));
    return small ? PoissonSolver::SparseNormalCholesky : l1 ? PoissonSolver::EigenCg : PoissonSolver::Cosine;
}

// Called with the linear problems (one per channel) a ChannelSolver has solved so far.
using SolveProgress = std::function<void(int done)>;

// One linear problem at a time (L2's, or an IRLS step's), all three channels from their current values (the warm
// start) to the solution, with the solver chosen: Ceres's, Eigen CG on the assembled normal equations, or the
// cosine transform.
class ChannelSolver {
public:
    ChannelSolver(const GradientImage& image, const ReconstructSettings& settings, PoissonSolver solver,
                  ReconstructStatistics& statistics, const SolveProgress& progress)
        : image_(image), settings_(settings), solver_(solver), statistics_(statistics), progress_(progress),
          arena_(settings.threads) {
        const bool l1 = settings.norm == ReconstructNorm::L1;
        maxLinearIterations_ = settings.maxLinearIterations;
        if (maxLinearIterations_ == 0)
            maxLinearIterations_ = !l1                                ? 500
                                   : solver == PoissonSolver::EigenCg ? kEigenCgL1Iterations
                                   : solver == PoissonSolver::Cosine  ? kCosineL1Iterations
                                                                      : 50;
        if (solver == PoissonSolver::EigenCg) {
            statistics.solver = "EIGEN_CG";
        } else if (solver == PoissonSolver::Cosine) {
            statistics.solver = "DCT";
            transform_.emplace(image.width, image.height);
        } else {
            setUpCeres();
        }
    }

    void solve(const ResidualWeights& weights, Solution& x) {
        if (solver_ != PoissonSolver::EigenCg && solver_ != PoissonSolver::Cosine)
            solveCeres(weights, x);
        else
            solveEigen(weights, x);
    }

private:
    void setUpCeres() {
        options_.linear_solver_type =
            solver_ == PoissonSolver::SparseNormalCholesky ? ceres::SPARSE_NORMAL_CHOLESKY : ceres::CGNR;
        options_.preconditioner_type = ceres::JACOBI;
        options_.num_threads = settings_.threads;
        options_.logging_type = ceres::SILENT;
        // The problem is linear least squares: with an (effectively) unbounded trust region the first
        // Levenberg-Marquardt step is the Gauss-Newton step, i.e. the solution of the normal equations
        // (the screened Poisson equation), so one iteration suffices.
        options_.initial_trust_region_radius = 1e16;
        options_.max_trust_region_radius = 1e16;
        options_.max_num_iterations = 1;
        // CGNR: GPT's presets cap the CG steps (L2Q 500, L1D 50 per reweighting step). eta, Ceres's
        // threshold on the relative decrease of the quadratic model, is tight, so CG runs to its own
        // convergence or the cap (1280x720, alpha 0.2: about 55 steps, the final cost of sparse Cholesky).
        options_.max_linear_solver_iterations = maxLinearIterations_;
        options_.eta = 1e-10;
        statistics_.solver = ceres::LinearSolverTypeToString(options_.linear_solver_type);
        ceresProblem_.emplace(image_, settings_.alpha);
    }

    void solveCeres(const ResidualWeights& weights, Solution& x) {
        ceresProblem_->setWeights(weights);
        for (size_t c = 0; c < 3; ++c) {
            const ceres::Solver::Summary summary = ceresProblem_->solve(c, x[c], options_);
            ++statistics_.solves;
            // summary.iterations starts with iteration 0, the evaluation at the starting point.
            statistics_.solverIterations += int(summary.iterations.size()) - 1;
            for (const auto& it : summary.iterations)
                statistics_.linearIterations += it.linear_solver_iterations;
            if (progress_) progress_(++done_);
        }
    }

    // The weights are shared by R, G and B, so one matrix (or one constant-weight operator) serves the three
    // channels, solved in parallel (each CG is a chain of dependent mat-vecs, each cosine solve two transforms;
    // three are the parallelism there is). Constant weights (L2) make the cosine transform's solve exact: one
    // "iteration", and no matrix at all (the residual is computed from the stencil, as a check).
    void solveEigen(const ResidualWeights& weights, Solution& x) {
        const size_t N = image_.pixels();
        const double alpha = settings_.alpha;
        const bool exactCosine = solver_ == PoissonSolver::Cosine && weights.primal.empty();
        if (!exactCosine) assembleNormalMatrix(image_.width, image_.height, alpha, weights, A_);
        const ScreenedLaplacian op = solver_ == PoissonSolver::Cosine
                                         ? harmonicWeightOperator(alpha, weights, image_.width, image_.height)
                                         : ScreenedLaplacian{};
        std::array<ConjugateGradientResult, 3> results;
        arena_.execute([&] {
            tbb::parallel_for(size_t(0), size_t(3), [&](size_t c) {
                Eigen::VectorXd b;
                normalRightHandSide(image_, c, alpha, weights, b);
                Eigen::Map<Eigen::VectorXd> xc(x[c].data(), Eigen::Index(N));
                if (exactCosine) {
                    xc = b;
                    transform_->solve(op, xc);
                    results[c] = {1, normalResidual(image_.width, image_.height, alpha, weights, b, xc)};
                } else if (solver_ == PoissonSolver::Cosine) {
                    results[c] =
                        solveNormalEquationsCosine(A_, b, *transform_, op, kEigenCgTolerance, maxLinearIterations_, xc);
                } else {
                    results[c] = solveNormalEquations(A_, b, kEigenCgTolerance, maxLinearIterations_, xc);
                }
            });
        });
        for (const auto& r : results) {
            ++statistics_.solves;
            ++statistics_.solverIterations;
            statistics_.linearIterations += r.iterations;
            statistics_.linearResidual = std::max(statistics_.linearResidual, r.relativeResidual);
        }
        done_ += 3;
        if (progress_) progress_(done_);
    }

    const GradientImage& image_;
    const ReconstructSettings& settings_;
    PoissonSolver solver_;
    ReconstructStatistics& statistics_;
    const SolveProgress& progress_;
    int done_ = 0, maxLinearIterations_ = 0;
    std::optional<ChannelProblem> ceresProblem_;
    ceres::Solver::Options options_;
    std::optional<CosinePoisson> transform_;
    NormalMatrix A_;
    tbb::task_arena arena_;
};

// The image: the solution with the directly seen emitters added back.
RgbPlanes developSolution(const GradientImage& image, const Solution& x) {
    RgbPlanes out;
    for (size_t c = 0; c < 3; ++c) {
        out[c].resize(image.pixels());
        for (size_t p = 0; p < image.pixels(); ++p) {
            const double v = x[c][p] + (image.direct ? (*image.direct)[c][p] : 0.0f);
            // Finite inputs and a positive alpha make the system positive definite, so this would be a
            // solver bug; it must not reach a file as NaN or Inf.
            if (!std::isfinite(float(v))) throw Error("reconstruction: the solver produced a non-finite value");
            out[c][p] = float(v);
        }
    }
    return out;
}

// Sum over pixels and R, G, B of the planes (x, or the primal when x is null), the direct plane included.
double imageSum(const GradientImage& image, const Solution* x) {
    double sum = 0;
    for (size_t c = 0; c < 3; ++c)
        for (size_t p = 0; p < image.pixels(); ++p)
            sum += (x ? (*x)[c][p] : double(image.primal[c][p])) + (image.direct ? (*image.direct)[c][p] : 0.0f);
    return sum;
}

// x's mean relative to the primal's, minus one (0 for a black primal).
double meanShift(const GradientImage& image, const Solution& x) {
    const double primal = imageSum(image, nullptr);
    return primal != 0 ? imageSum(image, &x) / primal - 1 : 0.0;
}

// Minimizes the norm's objective from the primal (the warm start) and returns the minimizer.
Solution minimize(const GradientImage& image, const ReconstructSettings& settings, ReconstructStatistics& statistics,
                  const SolveProgress& progress) {
    ChannelSolver solver(image, settings, statistics.solverUsed, statistics, progress);
    Solution x;
    for (size_t c = 0; c < 3; ++c)
        x[c].assign(image.primal[c].begin(), image.primal[c].end());
    statistics.initialCost = objective(image, x, settings.alpha, settings.norm);
    // L1 reweights from the primal (the warm start above), not from the L2 solution: L2 spreads every
    // outlier gradient over its neighbourhood, and the first weights then trust the spread, not the
    // outlier. Measured on 32x32 with 1% of the gradients +-1e6 (noise 0.05 / 0.01), MSE against the
    // truth from the L2 start / from the primal: Ceres's Cholesky 0.70 / 2.4e-4, Eigen CG 4.9e5 / 8.0e-5,
    // DCT 4.8e7 / 7.5e-5 (the iterative solvers cannot undo a spread of 1e4 with weights 1e13 apart); on
    // the 1280x720 bench input (outliers 100) the same MSE (Eigen CG 1.55e-3 / 1.55e-3) and objective
    // (183039 / 183043). The primal's zero residuals get weight 1 / reg0 (20) against ~8 for a gradient
    // residual of the noise level, which does not pin the image to it.
    ResidualWeights weights; // empty: L2
    if (settings.norm == ReconstructNorm::L2) {
        solver.solve(weights, x);
    } else {
        double reg = settings.irlsRegularizer;
        for (int it = 0; it < settings.irlsIterations; ++it, reg *= settings.irlsDecay) {
            irlsWeights(image, x, settings.alpha, reg, weights);
            solver.solve(weights, x);
            ++statistics.irlsIterations;
        }
    }
    statistics.finalCost = objective(image, x, settings.alpha, settings.norm);
    return x;
}

// I_L1 + S (P - I_L1) (screened_poisson.h): the primal's residual smoothed by the L2 reconstruction of an image
// without gradients, with alpha = 1 / meanScale. Its solves are counted apart from the norm's (`statistics`'s
// meanSolves and meanSolver).
void restoreMean(const GradientImage& image, const ReconstructSettings& settings, Solution& x,
                 ReconstructStatistics& statistics, const SolveProgress& progress) {
    GradientImage residual;
    residual.width = image.width;
    residual.height = image.height;
    for (size_t c = 0; c < 3; ++c) {
        residual.primal[c].resize(image.pixels());
        for (size_t p = 0; p < image.pixels(); ++p)
            residual.primal[c][p] = float(image.primal[c][p] - x[c][p]);
        residual.dx[c].assign(image.pixels(), 0.0f);
        residual.dy[c].assign(image.pixels(), 0.0f);
    }
    ReconstructSettings smoothing = settings;
    smoothing.norm = ReconstructNorm::L2;
    smoothing.alpha = 1 / settings.meanScale;
    smoothing.maxLinearIterations = 0;
    // Auto's solvers for L2 (Ceres's Cholesky, the cosine transform) are exact, so the mean comes back exactly
    // whatever solver the L1 steps used (Eigen CG to its tolerance of 1e-5 left the mean 2e-5 off).
    smoothing.solver = PoissonSolver::Auto;
    ReconstructStatistics own;
    own.solverUsed = chooseSolver(smoothing, image.pixels(), own);
    const Solution smooth = minimize(residual, smoothing, own, progress);
    for (size_t c = 0; c < 3; ++c)
        for (size_t p = 0; p < image.pixels(); ++p)
            x[c][p] += smooth[c][p];
    statistics.meanSolves = own.solves;
    statistics.meanSolver = own.solver;
    statistics.meanScale = settings.meanScale;
}

} // namespace

std::string normName(ReconstructNorm norm) { return norm == ReconstructNorm::L2 ? "l2" : "l1"; }

file::Buffer reconstructScreenedPoisson(const GradientImage& image, const ReconstructSettings& settings,
                                        ReconstructStatistics& statistics, const ReconstructProgress& progress) {
    checkSettings(settings);
    const auto start = std::chrono::steady_clock::now();
    statistics = {};
    statistics.norm = normName(settings.norm);
    statistics.alpha = settings.alpha;
    statistics.solverUsed = chooseSolver(settings, image.pixels(), statistics);
    const bool l1 = settings.norm == ReconstructNorm::L1;
    const bool restore = l1 && settings.mean == MeanRestoration::Kept;
    // Linear problems in all: three channels per L2 solve or IRLS step, and three for the restoration.
    const int problems = 3 * (l1 ? settings.irlsIterations : 1), total = problems + (restore ? 3 : 0);
    const SolveProgress counted = [&](int done) {
        if (progress) progress(done, total);
    };
    Solution x = minimize(image, settings, statistics, counted);
    statistics.solveMeanShift = meanShift(image, x);
    const SolveProgress restoring = [&](int done) {
        if (progress) progress(problems + done, total);
    };
    if (restore) restoreMean(image, settings, x, statistics, restoring);
    statistics.meanShift = meanShift(image, x);
    RgbPlanes out = developSolution(image, x);
    statistics.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return rgbBuffer(image.width, image.height, std::move(out));
}

} // namespace lt
