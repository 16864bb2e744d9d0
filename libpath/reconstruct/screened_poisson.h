// Screened Poisson reconstruction of a gradient-domain render, L2 and L1, solved with Ceres, Eigen CG or
// the cosine transform (Bauszat et al. 2017, Sec. 2.2 and 4; the solver schedule follows the code of
// Kettunen et al. 2015).
//   L2: min_I  alpha^2 |I - P|^2 + |Dx I - Gx|^2 + |Dy I - Gy|^2          (unbiased: linear in P, G)
//   L1: min_I  sum_p |alpha (I - P)_p| + |(Dx I - Gx)_p| + |(Dy I - Gy)_p|  (per-pixel RGB vector norms)
// alpha multiplies the primal residual, so it enters the L2 objective squared.
//
// The image mean. L2 keeps the primal's: summed over the pixels its normal equations
// alpha^2 (I - P) + D^T (D I - G) = 0 leave alpha^2 sum (I - P) = 0, as D^T's columns sum to zero (a constant
// has no differences). L1 does not: it acts like a median, and on firefly-heavy renders (rare paths of
// high value, in the primal and in the gradients around it) it discards their energy: Kettunen et al. 2015
// call it biased but consistent; on door-ajar at 4 samples a pixel of G-PT (unbounded depth, 160x120) it
// moved the image mean by -45 to -51 % (pipelines/results/l1-mean/). With MeanRestoration::Kept (the default) the primal's residual r = P - I_L1, where that energy
// sits, is smoothed by the screened Poisson operator without gradients, S = (beta^2 + D^T D)^-1 beta^2 with
// beta = 1 / meanScale (a kernel of about meanScale pixels whose weights sum to one: the argument above
// with G = 0), and added back: I = I_L1 + S r. The result's mean is the primal's exactly, and every region
// of about meanScale pixels keeps its own mean, so the energy L1 took from a firefly comes back as a
// smooth glow around it rather than as the firefly: L1's robustness at the finest scales, the primal's
// mean at coarse ones. It is unbiased for the image mean and for every region's mean at scales well above
// meanScale, and keeps L1's (consistent) bias only in the detail below it.
#pragma once

#include <functional>
#include <string>

#include "formats/records.h"
#include "reconstruct/gradient_image.h"

namespace lt {

enum class ReconstructNorm { L2, L1 };
// Whether an L1 reconstruction's mean is restored to the primal's (see the top of this file).
enum class MeanRestoration {
    Kept, // I_L1 + S (P - I_L1): the primal's mean, L1's detail
    Free, // the L1 minimizer as the papers define it, its mean wherever it lands
};
enum class PoissonSolver {
    Auto,                 // Ceres's sparse Cholesky up to kCholeskyMaxPixels; above, Cosine for L2, EigenCg for L1
    SparseNormalCholesky, // Ceres, exact; memory and time grow faster than the image
    Cgnr,                 // Ceres, conjugate gradients on the normal equations, Jacobi preconditioned
    EigenCg,              // Eigen's conjugate gradients on the assembled normal equations, Jacobi preconditioned
    Cosine,               // the 2-D cosine transform: exact for L2; for L1 it preconditions Eigen's CG (dct_poisson.h)
};

// Images up to this many pixels are solved by Ceres's sparse Cholesky under PoissonSolver::Auto, larger
// ones by the cosine transform (L2) or Eigen CG (L1) (the measurements are at the choice, in
// screened_poisson.cpp).
inline constexpr size_t kCholeskyMaxPixels = 64 * 64;

// Eigen CG stops when |b - A I| <= kEigenCgTolerance |b| for the normal equations A I = b of a channel
// (or at the iteration cap). Measured at 1280x720 against Eigen's sparse LDL^T, from the primal, alpha
// 0.2: 1e-5 takes 59 steps and leaves an RMS difference of 8e-6 (max 4e-5) on values 0.2 .. 2.5, 4000
// times below the RMS error of the exact L2 solution itself (0.035 for primal noise 0.2, gradient noise
// 0.05); 1e-6 takes 75 steps for 8e-7.
inline constexpr double kEigenCgTolerance = 1e-5;

// Eigen CG's default cap per L1 linear solve. Each IRLS step starts from the previous one's result and
// only the last step's solution is kept, so the steps need not be exact: at 1280x720 (bench input,
// 2 threads) 10 steps per solve gave the same MSE against the truth as 50 (1.57e-3 vs 1.59e-3) and an
// L1 objective 1e-4 (relative) higher, in 9 s instead of 47 s.
inline constexpr int kEigenCgL1Iterations = 10;

// The cosine solver's default cap per L1 linear solve (CG preconditioned by the transform, dct_poisson.h).
// Measured at 1280x720 (bench input, 2 threads, a shared machine whose timings vary by 20-40%), L1
// objective at the end against Eigen CG's 183043 (10 Jacobi steps per solve, 10.7-16 s): 1 step 184075
// in 9.8 s, 3 steps 183177 in 17-19 s. A step costs a transform pair (56 ms single-threaded) besides the
// 18 ms mat-vec, and Eigen applies the preconditioner once more than it steps, so it buys no time over
// Jacobi; 3 steps keep the objective within 1e-3 of Eigen CG's. Without the diagonal scaling S (a
// constant operator alone: mean, median, geometric or harmonic mean of the weights) 3 steps left the
// objective 19% higher at 640x360.
inline constexpr int kCosineL1Iterations = 3;

// The size in pixels of the kernel that restores L1's mean (1 / beta above). pipelines/bench/l1-mean.sh,
// 160x120, 4 samples a pixel, 3 seeds, relMSE of L1 with the mean kept over 4 / 8 / 16 / 32 / 64 pixels:
// door-ajar G-PT 2.68 / 2.30 / 2.19 / 2.17 / 2.19 on the first seed (L2 3.67, L1 free 3.21), path reusing
// 2.19 / 1.87 / 1.75 / 1.71 / 1.70 (L2 1.47, free 1.72); window-room G-PT 0.108 / 0.101 / 0.101 / 0.101 / 0.102
// (L2 0.149, free 0.139), path reusing 0.073 / 0.068 / 0.066 / 0.066 / 0.065 (L2 0.072, free 0.066); the other
// seeds alike. The error falls to 16 pixels and is flat beyond, where a wider kernel only blurs each region's
// mean further: 16.
inline constexpr double kMeanScale = 16;

struct ReconstructSettings {
    ReconstructNorm norm = ReconstructNorm::L2;
    double alpha = 0.2;            // weight of the primal residual; > 0
    int irlsIterations = 20;       // L1: reweighting steps (GPT's L1D preset)
    double irlsRegularizer = 0.05; // L1: reg0 in w = 1 / (|e| + reg0 * decay^it)
    double irlsDecay = 0.5;        // L1: factor on the regularizer per step
    // Most CG iterations per linear solve (CGNR, Eigen CG, DCT's L1 steps); 0: 500 for L2 (GPT's L2Q), and
    // per L1 step 50 with CGNR (L1D), 10 with Eigen CG (kEigenCgL1Iterations) and 3 with DCT
    // (kCosineL1Iterations). DCT's L2 solves are exact and take no cap.
    int maxLinearIterations = 0;
    PoissonSolver solver = PoissonSolver::Auto;
    int threads = 1;
    MeanRestoration mean = MeanRestoration::Kept; // L1 only: L2 keeps the mean by itself
    double meanScale = kMeanScale;                // the restoring kernel's size in pixels (1 / beta); > 0
};

struct ReconstructStatistics {
    std::string norm; // "l2" or "l1"
    double alpha = 0;
    int irlsIterations = 0;   // reweighting steps done (0 for L2)
    int solves = 0;           // linear solves (one per channel and linear problem)
    int solverIterations = 0; // Ceres trust-region iterations, all solves (Eigen CG and DCT: 1 per solve)
    int linearIterations = 0; // linear solver iterations (CG steps; 1 per Cholesky or exact DCT solve), all solves
    double initialCost = 0;   // the objective above (of the chosen norm) at I = P
    double finalCost = 0;     // and at the result (both without the direct plane)
    double seconds = 0;       // wall time of the whole reconstruction
    std::string solver;       // the linear solver used: SPARSE_NORMAL_CHOLESKY, CGNR (Ceres), EIGEN_CG or DCT
    PoissonSolver solverUsed = PoissonSolver::Auto; // the same as an enum (never Auto)
    std::string solverReason; // why: "requested", or auto's rule: the pixel count and, above it, the norm
    // Eigen CG and DCT: the largest |b - A I| / |b| at the end of a solve (0 otherwise); for DCT's exact
    // solves computed from the stencil afterwards, so it shows the rounding error.
    double linearResidual = 0;
    // How far the image mean (over pixels and R, G, B, the direct plane included) moved from the primal's,
    // relative to it: by the norm's minimizer (L2: rounding, and the tolerance of eigen-cg or cgnr) and in the
    // image written (after the mean's restoration, if any). 0 for a black primal.
    double solveMeanShift = 0;
    double meanShift = 0;
    // The mean's restoration, apart from the figures above (which are the norm's minimizer's, finalCost included):
    // the kernel's size in pixels (0 when the mean was not restored), its linear solves and their solver (auto's
    // for L2: Ceres's sparse Cholesky or the cosine transform, both exact).
    double meanScale = 0;
    int meanSolves = 0;
    std::string meanSolver;
};

// Called after each linear problem: (problems done, problems in all); the tool shows it as progress.
using ReconstructProgress = std::function<void(int done, int total)>;

// The reconstructed image as an R, G, B buffer, the direct plane (if any) added back. The input must
// pass validateGradientImage; settings are checked here (alpha > 0 and finite, iterations >= 1, ...).
// Throws lt::Error when the settings are invalid or a solver fails.
[[nodiscard]] file::Buffer reconstructScreenedPoisson(const GradientImage& image, const ReconstructSettings& settings,
                                                      ReconstructStatistics& statistics,
                                                      const ReconstructProgress& progress = {});

[[nodiscard]] std::string normName(ReconstructNorm norm);

} // namespace lt
