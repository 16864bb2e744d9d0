// lt-reconstruct: the last stage of gradient-domain rendering, a screened Poisson reconstruction (L2 or
// L1) of an image from its noisy primal and noisy gradients, solved with Ceres, Eigen CG or the cosine
// transform.
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <thread>
#include <variant>

#include "common/info.h"
#include "common/interrupt.h"
#include "common/progress.h"
#include "common/tool.h"
#include "formats/ltfile.h"
#include "image/buffer_source.h"
#include "image/image_io.h"
#include "reconstruct/gradient_image.h"
#include "reconstruct/screened_poisson.h"

namespace {

bool isExrName(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (auto& ch : ext)
        ch = char(std::tolower(static_cast<unsigned char>(ch)));
    return ext == ".exr";
}

nlohmann::json toJson(const lt::ReconstructStatistics& s) {
    return {{"norm", s.norm},
            {"alpha", s.alpha},
            {"irls_iterations", s.irlsIterations},
            {"solves", s.solves},
            {"iterations", s.solverIterations},
            {"linear_iterations", s.linearIterations},
            {"initial_cost", s.initialCost},
            {"final_cost", s.finalCost},
            {"seconds", s.seconds},
            {"solver", s.solver},
            {"solver_reason", s.solverReason},
            {"linear_residual", s.linearResidual}};
}

// The STAT table "reconstruct" (formats/SPEC.md): numbers only, so the norm is its exponent (1 or 2)
// and the solver a code (1 Ceres sparse normal Cholesky, 2 Ceres CGNR, 3 Eigen CG, 4 DCT); INFO has them as
// names.
lt::file::StatTable toStatTable(const lt::ReconstructStatistics& s) {
    return lt::file::valueTable("reconstruct", {{"norm", s.norm == "l1" ? 1.0 : 2.0},
                                                {"alpha", s.alpha},
                                                {"irls_iterations", double(s.irlsIterations)},
                                                {"solves", double(s.solves)},
                                                {"iterations", double(s.solverIterations)},
                                                {"linear_iterations", double(s.linearIterations)},
                                                {"initial_cost", s.initialCost},
                                                {"final_cost", s.finalCost},
                                                {"seconds", s.seconds},
                                                {"solver", s.solverUsed == lt::PoissonSolver::Cgnr      ? 2.0
                                                           : s.solverUsed == lt::PoissonSolver::EigenCg ? 3.0
                                                           : s.solverUsed == lt::PoissonSolver::Cosine  ? 4.0
                                                                                                        : 1.0}});
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{
        "lt-reconstruct: screened Poisson reconstruction of a gradient-domain render, L2 or L1, solved with Ceres\n"
        "(sparse Cholesky, exact) up to 64x64 pixels; above, L2 exactly by the 2-D cosine transform and L1 with\n"
        "Eigen's conjugate gradients (see --solver).\n"
        "  L2: min_I alpha^2 |I - P|^2 + |Dx I - Gx|^2 + |Dy I - Gy|^2 (unbiased; linear in the inputs).\n"
        "  L1: the same with per-pixel RGB vector norms, not squared, by iteratively reweighted least squares:\n"
        "      biased (though consistent) but robust: far fewer artifacts from outlier gradients.\n"
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
    std::string input, output, primalPath, dxPath, dyPath, directPath, normText = "l2", solverText = "auto";
    lt::ReconstructSettings settings;
    int threads = 0;
    bool quiet = false;
    app.add_option("IN", input, "buffer file (.lts, - for stdin) or multi-layer EXR with primal, dx, dy");
    app.add_option("-o,--output", output, "reconstructed image: OUT.exr, or an lt buffer file (.lts, - for stdout)")
        ->required();
    auto* primalOpt = app.add_option("--primal", primalPath, "primal image (EXR or buffer file) instead of IN");
    auto* dxOpt = app.add_option("--dx", dxPath, "horizontal forward differences, with --primal");
    auto* dyOpt = app.add_option("--dy", dyPath, "vertical forward differences, with --primal");
    auto* directOpt = app.add_option("--direct", directPath, "directly visible emitters, added after the solve");
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
        if (input.empty() == primalPath.empty())
            throw lt::Error(input.empty() ? "no input: give IN, or --primal, --dx and --dy"
                                          : "give either IN or --primal, --dx and --dy, not both");
        settings.norm = normText == "l1" ? lt::ReconstructNorm::L1 : lt::ReconstructNorm::L2;
        settings.solver = solverText == "cholesky"   ? lt::PoissonSolver::SparseNormalCholesky
                          : solverText == "cgnr"     ? lt::PoissonSolver::Cgnr
                          : solverText == "eigen-cg" ? lt::PoissonSolver::EigenCg
                          : solverText == "dct"      ? lt::PoissonSolver::Cosine
                                                     : lt::PoissonSolver::Auto;
        settings.threads = threads > 0 ? threads : int(std::max(1u, std::thread::hardware_concurrency()));

        lt::tool::Progress progress("lt-reconstruct", quiet);
        lt::ReconstructStatistics stats;
        auto solve = [&](const lt::GradientImage& image) {
            return lt::reconstructScreenedPoisson(image, settings, stats, [&](int done, int total) {
                progress.update(double(done) / total,
                                std::to_string(done) + " of " + std::to_string(total) + " linear solves");
            });
        };
        nlohmann::json info = lt::tool::makeInfo("lt-reconstruct", argc, argv,
                                                 {{"norm", normText},
                                                  {"alpha", settings.alpha},
                                                  {"iterations", settings.irlsIterations},
                                                  {"irls_reg", settings.irlsRegularizer},
                                                  {"irls_decay", settings.irlsDecay},
                                                  {"max_solver_iterations", settings.maxLinearIterations},
                                                  {"solver", solverText},
                                                  {"threads", settings.threads}},
                                                 nullptr);
        uint32_t width = 0, height = 0;
        bool cut = false; // a signal stopped the stream early
        if (!input.empty() && (input == "-" || !lt::isExrFile(input)) && !isExrName(output)) {
            // An lt buffer file into an lt buffer file: streamed, every snapshot reconstructed on the way.
            lt::file::Reader reader(input, lt::file::FileKind::Buffer);
            info["input"] = reader.name();
            if (reader.info().is_object() && reader.info().contains("scene")) info["scene"] = reader.info()["scene"];
            lt::file::Writer writer(output, lt::file::FileKind::Buffer, info);
            std::optional<lt::file::Buffer> last, lastSnapshot;
            size_t snapshots = 0;
            // Ctrl-C or SIGTERM while the stream comes in: the solve under way finishes, the stream is left
            // (its producer gets a broken pipe), the newest buffer read is reconstructed and the file is
            // complete (exit 130 or 143). A single image has nothing to cut: a signal kills as usual.
            lt::tool::installInterruptHandler();
            for (;;) {
                if (lt::tool::stopRequested()) {
                    cut = true;
                    break;
                }
                lt::file::Chunk chunk = reader.next();
                if (std::holds_alternative<lt::file::End>(chunk)) break;
                if (auto* b = std::get_if<lt::file::Buffer>(&chunk)) last = std::move(*b);
                if (auto* snap = std::get_if<lt::file::Snapshot>(&chunk)) {
                    ++snapshots;
                    const lt::GradientImage image = lt::gradientImageFromBuffer(
                        snap->buffer, reader.name() + " (snapshot " + std::to_string(snapshots) + ")");
                    lt::file::Snapshot out = *snap;
                    out.buffer = solve(image);
                    // The image of this snapshot cost its render time and this reconstruction.
                    out.wallSeconds += stats.seconds;
                    out.cpuSeconds += stats.seconds;
                    writer.writeSnapshot(out);
                    lastSnapshot = std::move(snap->buffer);
                }
            }
            if (!last && !lastSnapshot) throw lt::Error(reader.name() + ": holds no buffer (no BUFR or SNAP chunk)");
            const lt::GradientImage image = lt::gradientImageFromBuffer(last ? *last : *lastSnapshot, reader.name());
            width = image.width;
            height = image.height;
            writer.writeBuffer(solve(image));
            writer.writeStats(toStatTable(stats));
            writer.finish();
        } else {
            lt::GradientImage image;
            if (!input.empty()) {
                lt::BufferSource source = lt::loadBuffer(input);
                image = lt::gradientImageFromBuffer(source.buffer, source.name);
                info["input"] = source.name;
                if (source.info.is_object() && source.info.contains("scene")) info["scene"] = source.info["scene"];
            } else {
                const lt::BufferSource p = lt::loadBuffer(primalPath), dx = lt::loadBuffer(dxPath),
                                       dy = lt::loadBuffer(dyPath);
                std::optional<lt::BufferSource> direct;
                if (!directPath.empty()) direct = lt::loadBuffer(directPath);
                image = lt::gradientImageFromLayers(
                    {&p.buffer, p.name}, {&dx.buffer, dx.name}, {&dy.buffer, dy.name},
                    direct ? std::optional<lt::LayerSource>({&direct->buffer, direct->name}) : std::nullopt);
                info["input"] = p.name;
            }
            width = image.width;
            height = image.height;
            const lt::file::Buffer result = solve(image);
            info["reconstruct"] = toJson(stats);
            if (isExrName(output)) {
                lt::writeExr(output, result, info);
            } else {
                lt::file::Writer writer(output, lt::file::FileKind::Buffer, info);
                writer.writeBuffer(result);
                writer.writeStats(toStatTable(stats));
                writer.finish();
            }
        }
        progress.finish();
        if (cut && !quiet)
            std::cerr
                << "lt-reconstruct: interrupted: the input's rest was not read; reconstructed its newest buffer\n";
        if (!quiet) {
            std::ostringstream residual; // the accuracy of Eigen CG or DCT, which measure it
            if (stats.solverUsed == lt::PoissonSolver::EigenCg || stats.solverUsed == lt::PoissonSolver::Cosine)
                residual << ", relative residual <= " << stats.linearResidual;
            std::cerr << "lt-reconstruct: " << stats.norm << ", alpha " << stats.alpha << ", " << width << "x" << height
                      << ": " << (stats.irlsIterations ? std::to_string(stats.irlsIterations) + " IRLS steps, " : "")
                      << stats.solves << " solves with " << stats.solver << " (" << stats.solverReason << "), "
                      << stats.solverIterations << " iterations, " << stats.linearIterations
                      << " linear solver iterations" << residual.str() << "; cost " << stats.initialCost << " -> "
                      << stats.finalCost << "; " << stats.seconds << " s; wrote "
                      << (output == "-" ? std::string("<stdout>") : output) << '\n';
        }
        return cut ? lt::tool::interruptedExitCode() : 0;
    });
}
