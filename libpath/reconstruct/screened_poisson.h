// Screened Poisson reconstruction of a gradient-domain render, L2 and L1, solved with Ceres
// (ALGORITHMS.md 7; [GDPR] Sec. 2.2, 4; the solver schedule follows Kettunen's GPT code).
//   L2: min_I  alpha^2 |I - P|^2 + |Dx I - Gx|^2 + |Dy I - Gy|^2          (unbiased: linear in P, G)
//   L1: min_I  sum_p |alpha (I - P)_p| + |(Dx I - Gx)_p| + |(Dy I - Gy)_p|  (per-pixel RGB vector norms)
// alpha multiplies the primal residual, so it enters the L2 objective squared.
#pragma once

#include <functional>
#include <string>

#include "formats/records.h"
#include "reconstruct/gradient_image.h"

namespace lt {

enum class ReconstructNorm { L2, L1 };
enum class PoissonSolver {
    Auto,                 // sparse Cholesky up to kCholeskyMaxPixels, CGNR above
    SparseNormalCholesky, // exact; memory and time grow faster than the image
    Cgnr,                 // conjugate gradients on the normal equations, Jacobi preconditioned
};

// Images up to this many pixels are solved by sparse Cholesky under PoissonSolver::Auto (measured in
// pipelines/bench/reconstruct.sh: beyond it CGNR is faster and needs far less memory).
inline constexpr size_t kCholeskyMaxPixels = 256 * 256;

struct ReconstructSettings {
    ReconstructNorm norm = ReconstructNorm::L2;
    double alpha = 0.2;            // weight of the primal residual; > 0
    int irlsIterations = 20;       // L1: reweighting steps (GPT's L1D preset)
    double irlsRegularizer = 0.05; // L1: reg0 in w = 1 / (|e| + reg0 * decay^it)
    double irlsDecay = 0.5;        // L1: factor on the regularizer per step
    // Most CG iterations per linear solve (CGNR only); 0: 500 for L2 (GPT's L2Q) and 50 per L1 step (L1D).
    int maxLinearIterations = 0;
    PoissonSolver solver = PoissonSolver::Auto;
    int threads = 1;
};

struct ReconstructStatistics {
    std::string norm; // "l2" or "l1"
    double alpha = 0;
    int irlsIterations = 0;   // reweighting steps done (0 for L2)
    int solves = 0;           // Ceres solves (one per channel and linear problem)
    int solverIterations = 0; // Ceres trust-region iterations, all solves
    int linearIterations = 0; // linear solver iterations (CG steps; 1 per Cholesky solve), all solves
    double initialCost = 0;   // the objective above (of the chosen norm) at I = P
    double finalCost = 0;     // and at the result (both without the direct plane)
    double seconds = 0;       // wall time of the whole reconstruction
    std::string solver;       // the Ceres linear solver used
};

// Called after each linear problem: (problems done, problems in all); the tool shows it as progress.
using ReconstructProgress = std::function<void(int done, int total)>;

// The reconstructed image as an R, G, B buffer, the direct plane (if any) added back. The input must
// pass validateGradientImage; settings are checked here (alpha > 0 and finite, iterations >= 1, ...).
// Throws lt::Error when the settings are invalid or Ceres fails.
[[nodiscard]] file::Buffer reconstructScreenedPoisson(const GradientImage& image, const ReconstructSettings& settings,
                                                      ReconstructStatistics& statistics,
                                                      const ReconstructProgress& progress = {});

[[nodiscard]] std::string normName(ReconstructNorm norm);

} // namespace lt
