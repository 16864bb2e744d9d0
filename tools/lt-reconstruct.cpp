// lt-reconstruct: the last stage of gradient-domain rendering, a screened Poisson reconstruction (L2 or
// L1) of an image from its noisy primal and noisy gradients, solved with Ceres, Eigen CG or the cosine
// transform.
#include <iostream>
#include <thread>

#include "common/info.h"
#include "common/interrupt.h"
#include "common/progress.h"
#include "common/tool.h"
#include "reconstruct/reconstruct_files.h"

int main(int argc, char** argv) {
    CLI::App app{
        "lt-reconstruct: screened Poisson reconstruction of a gradient-domain render, L2 or L1, solved with Ceres\n"
        "(sparse Cholesky, exact) up to 64x64 pixels; above, L2 exactly by the 2-D cosine transform and L1 with\n"
        "Eigen's conjugate gradients (see --solver).\n"
        "  L2: min_I alpha^2 |I - P|^2 + |Dx I - Gx|^2 + |Dy I - Gy|^2 (unbiased; linear in the inputs).\n"
        "  L1: the same with per-pixel RGB vector norms, not squared, by iteratively reweighted least squares:\n"
        "      robust (far fewer artifacts from outlier gradients) but biased, though consistent: like a median it\n"
        "      drops the energy of fireflies, which moves the image mean (by half on firefly-heavy renders). By\n"
        "      default (--mean kept) the primal's residual P - I_L1 is smoothed over --mean-scale pixels and added\n"
        "      back, which restores the primal's mean exactly and each region's at coarser scales (see --mean).\n"
        "The summary line and the STAT table give how far the minimizer moved the mean and where it ended.\n"
        "Conventions (those of the public gradient-domain code): forward differences dx(x,y) = I(x+1,y) - I(x,y),\n"
        "dy(x,y) = I(x,y+1) - I(x,y), rows top to bottom, the last column of dx and last row of dy unused. alpha\n"
        "multiplies the primal residual, so it enters the L2 objective squared; larger alpha trusts the primal more.\n"
        "Input: channels primal.R/G/B, dx.R/G/B, dy.R/G/B and optionally direct.R/G/B (directly visible emitters,\n"
        "kept out of the solve and added back) of an lt buffer file or a multi-layer EXR; or separate images with\n"
        "--primal, --dx, --dy (each with R, G, B or its layer's channels). Output by extension: .exr, or an lt\n"
        "buffer file (.lts, - for stdout) with channels R, G, B and the solver statistics in a STAT table. From an\n"
        "lt buffer file to an lt buffer file every progress snapshot (lt-gradient --snapshots) is reconstructed\n"
        "too, its times increased by its reconstruction's, so lt-error measures reconstructed images against time.",
        "lt-reconstruct"};
    lt::ReconstructInputs in;
    std::string output, normText = "l2", solverText = "auto";
    lt::ReconstructSettings settings;
    int threads = 0;
    bool quiet = false;
    app.add_option("IN", in.input, "buffer file (.lts, - for stdin) or multi-layer EXR with primal, dx, dy");
    app.add_option("-o,--output", output, "reconstructed image: OUT.exr, or an lt buffer file (.lts, - for stdout)")
        ->required();
    auto* primalOpt = app.add_option("--primal", in.primal, "primal image (EXR or buffer file) instead of IN");
    auto* dxOpt = app.add_option("--dx", in.dx, "horizontal forward differences, with --primal");
    auto* dyOpt = app.add_option("--dy", in.dy, "vertical forward differences, with --primal");
    auto* directOpt = app.add_option("--direct", in.direct, "directly visible emitters, added after the solve");
    primalOpt->needs(dxOpt, dyOpt);
    dxOpt->needs(primalOpt);
    dyOpt->needs(primalOpt);
    directOpt->needs(primalOpt);
    app.add_option("--norm", normText,
                   "l2 (default: unbiased, so a reconstruction converges to the true image and runs merge and "
                   "compare against references as renders do; fast) or l1 (robust to outlier gradients, fewer "
                   "artifacts at low sample counts, but biased)")
        ->check(CLI::IsMember({"l1", "l2"}));
    app.add_option("--alpha", settings.alpha, "weight of the primal residual (default 0.2); must be > 0");
    std::string meanText = "kept";
    app.add_option("--mean", meanText,
                   "l1: kept (default: the energy L1 takes from fireflies comes back as a smooth glow of about "
                   "--mean-scale pixels around them, so the image mean is the primal's and L1's robustness stays "
                   "at finer scales) or free (the L1 minimizer of the papers, whose mean can land far from the "
                   "primal's); L2 keeps the mean by itself")
        ->check(CLI::IsMember({"kept", "free"}));
    app.add_option("--mean-scale", settings.meanScale,
                   "l1 with --mean kept: size in pixels of the kernel that restores the mean (default 16); larger "
                   "spreads a firefly's energy wider (less noise, more local bias), smaller comes closer to the "
                   "primal")
        ->check(lt::tool::PositiveNumber);
    app.add_option("--iterations", settings.irlsIterations, "L1: reweighting (IRLS) steps (default 20)")
        ->check(lt::tool::PositiveNumber);
    app.add_option("--irls-reg", settings.irlsRegularizer,
                   "L1: initial regularizer reg0 of the weights 1 / (|e| + reg) (default 0.05)");
    app.add_option("--irls-decay", settings.irlsDecay, "L1: factor on the regularizer per step (default 0.5)");
    app.add_option("--max-solver-iterations", settings.maxLinearIterations,
                   "most CG iterations per linear solve with cgnr, eigen-cg or dct's L1 steps (default 500 for L2; "
                   "per L1 step 50 with cgnr, 10 with eigen-cg, 3 with dct)")
        ->check(lt::tool::NonNegativeNumber);
    app.add_option("--solver", solverText,
                   "linear solver: cholesky (Ceres's sparse normal Cholesky: exact, but memory and time grow "
                   "fast), cgnr (Ceres's conjugate gradients: ~20x slower than eigen-cg at 1280x720, from Ceres's "
                   "problem setup and single-threaded products), eigen-cg (Eigen's Jacobi-preconditioned "
                   "conjugate gradients on the assembled normal equations, to a relative residual of 1e-5), dct "
                   "(the normal equations of L2 diagonalized by the 2-D discrete cosine transform: exact, "
                   "O(N log N), ~10x faster than eigen-cg at 1280x720; for L1's reweighted steps the transform "
                   "preconditions CG, which measured no faster than eigen-cg), or auto (default: cholesky up to "
                   "64x64 pixels; above, dct for L2 and eigen-cg for L1); the statistics say which and why")
        ->check(CLI::IsMember({"auto", "cholesky", "cgnr", "eigen-cg", "dct"}));
    app.add_option("--threads", threads,
                   "threads for Ceres, and for eigen-cg's and dct's channels (default: all cores)")
        ->check(lt::tool::ThreadCount);
    app.add_flag("-q,--quiet", quiet, "no progress or statistics output");
    return lt::tool::run(app, argc, argv, [&] {
        settings.norm = normText == "l1" ? lt::ReconstructNorm::L1 : lt::ReconstructNorm::L2;
        settings.mean = meanText == "free" ? lt::MeanRestoration::Free : lt::MeanRestoration::Kept;
        settings.solver = solverText == "cholesky"   ? lt::PoissonSolver::SparseNormalCholesky
                          : solverText == "cgnr"     ? lt::PoissonSolver::Cgnr
                          : solverText == "eigen-cg" ? lt::PoissonSolver::EigenCg
                          : solverText == "dct"      ? lt::PoissonSolver::Cosine
                                                     : lt::PoissonSolver::Auto;
        settings.threads = threads > 0 ? threads : int(std::max(1u, std::thread::hardware_concurrency()));
        const nlohmann::json info = lt::tool::makeInfo("lt-reconstruct", argc, argv,
                                                       {{"norm", normText},
                                                        {"alpha", settings.alpha},
                                                        {"mean", meanText},
                                                        {"mean_scale", settings.meanScale},
                                                        {"iterations", settings.irlsIterations},
                                                        {"irls_reg", settings.irlsRegularizer},
                                                        {"irls_decay", settings.irlsDecay},
                                                        {"max_solver_iterations", settings.maxLinearIterations},
                                                        {"solver", solverText},
                                                        {"threads", settings.threads}},
                                                       nullptr);
        // Ctrl-C or SIGTERM cuts a streamed input short and keeps its newest buffer (exit 130 or 143); a single
        // image has nothing to cut: a signal kills as usual.
        if (lt::streamsInput(in, output)) lt::tool::installInterruptHandler();
        lt::tool::Progress progress("lt-reconstruct", quiet);
        const lt::ReconstructOutcome out = lt::reconstructFiles(
            in, output, settings, info,
            [&](int done, int total) {
                progress.update(double(done) / total,
                                std::to_string(done) + " of " + std::to_string(total) + " linear solves");
            },
            &lt::tool::stopRequested());
        progress.finish();
        if (!quiet) {
            if (out.interrupted)
                std::cerr << "lt-reconstruct: interrupted: the input's rest was not read; reconstructed its newest "
                             "buffer\n";
            std::cerr << "lt-reconstruct: " << lt::reconstructSummary(out) << "; wrote "
                      << (output == "-" ? std::string("<stdout>") : output) << '\n';
        }
        return out.interrupted ? lt::tool::interruptedExitCode() : 0;
    });
}
