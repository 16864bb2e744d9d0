#include "reconstruct/reconstruct_files.h"

#include <filesystem>
#include <iomanip>
#include <optional>
#include <sstream>
#include <variant>

#include "formats/ltfile.h"
#include "image/buffer_source.h"
#include "image/image_io.h"
#include "reconstruct/gradient_image.h"
#include "util/error.h"

namespace lt {

namespace {

bool isExrName(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (auto& ch : ext)
        ch = char(std::tolower(static_cast<unsigned char>(ch)));
    return ext == ".exr";
}

// The input's scene, for the output's INFO.
void recordScene(const nlohmann::json& from, nlohmann::json& info) {
    if (from.is_object() && from.contains("scene")) info["scene"] = from["scene"];
}

// An lt buffer file into an lt buffer file: streamed, every snapshot reconstructed on the way. A stop while the
// stream comes in: the solve under way finishes, the stream is left (its producer gets a broken pipe), the newest
// buffer read is reconstructed and the file is complete.
ReconstructOutcome reconstructStream(const std::string& input, const std::string& output,
                                     const ReconstructSettings& settings, nlohmann::json info,
                                     const ReconstructProgress& progress, const std::atomic<bool>* stop) {
    ReconstructOutcome out;
    file::Reader reader(input, file::FileKind::Buffer);
    info["input"] = reader.name();
    recordScene(reader.info(), info);
    file::Writer writer(output, file::FileKind::Buffer, info);
    std::optional<file::Buffer> last, lastSnapshot;
    size_t snapshots = 0;
    for (;;) {
        if (stop && stop->load()) {
            out.interrupted = true;
            break;
        }
        file::Chunk chunk = reader.next();
        if (std::holds_alternative<file::End>(chunk)) break;
        if (auto* b = std::get_if<file::Buffer>(&chunk)) last = std::move(*b);
        if (auto* snap = std::get_if<file::Snapshot>(&chunk)) {
            ++snapshots;
            const GradientImage image =
                gradientImageFromBuffer(snap->buffer, reader.name() + " (snapshot " + std::to_string(snapshots) + ")");
            file::Snapshot reconstructed = *snap;
            reconstructed.buffer = reconstructScreenedPoisson(image, settings, out.stats, progress);
            // The image of this snapshot cost its render time and this reconstruction.
            reconstructed.wallSeconds += out.stats.seconds;
            reconstructed.cpuSeconds += out.stats.seconds;
            writer.writeSnapshot(reconstructed);
            lastSnapshot = std::move(snap->buffer);
        }
    }
    if (!last && !lastSnapshot) throw Error(reader.name() + ": holds no buffer (no BUFR or SNAP chunk)");
    const GradientImage image = gradientImageFromBuffer(last ? *last : *lastSnapshot, reader.name());
    out.width = image.width;
    out.height = image.height;
    writer.writeBuffer(reconstructScreenedPoisson(image, settings, out.stats, progress));
    writer.writeStats(reconstructTable(out.stats));
    writer.finish();
    return out;
}

// The render as one image: IN (an EXR, or a buffer file written out as EXR) or the layers apart.
GradientImage readImage(const ReconstructInputs& inputs, nlohmann::json& info) {
    if (!inputs.input.empty()) {
        BufferSource source = loadBuffer(inputs.input);
        info["input"] = source.name;
        recordScene(source.info, info);
        return gradientImageFromBuffer(source.buffer, source.name);
    }
    const BufferSource p = loadBuffer(inputs.primal), dx = loadBuffer(inputs.dx), dy = loadBuffer(inputs.dy);
    std::optional<BufferSource> direct;
    if (!inputs.direct.empty()) direct = loadBuffer(inputs.direct);
    info["input"] = p.name;
    return gradientImageFromLayers({&p.buffer, p.name}, {&dx.buffer, dx.name}, {&dy.buffer, dy.name},
                                   direct ? std::optional<LayerSource>({&direct->buffer, direct->name}) : std::nullopt);
}

} // namespace

bool streamsInput(const ReconstructInputs& inputs, const std::string& output) {
    return !inputs.input.empty() && (inputs.input == "-" || !isExrFile(inputs.input)) && !isExrName(output);
}

ReconstructOutcome reconstructFiles(const ReconstructInputs& inputs, const std::string& output,
                                    const ReconstructSettings& settings, nlohmann::json info,
                                    const ReconstructProgress& progress, const std::atomic<bool>* stop) {
    if (inputs.input.empty() == inputs.primal.empty())
        throw Error(inputs.input.empty() ? "no input: give IN, or --primal, --dx and --dy"
                                         : "give either IN or --primal, --dx and --dy, not both");
    if (streamsInput(inputs, output))
        return reconstructStream(inputs.input, output, settings, std::move(info), progress, stop);
    ReconstructOutcome out;
    const GradientImage image = readImage(inputs, info);
    out.width = image.width;
    out.height = image.height;
    const file::Buffer result = reconstructScreenedPoisson(image, settings, out.stats, progress);
    info["reconstruct"] = reconstructRecord(out.stats);
    if (isExrName(output)) {
        writeExr(output, result, info);
        return out;
    }
    file::Writer writer(output, file::FileKind::Buffer, info);
    writer.writeBuffer(result);
    writer.writeStats(reconstructTable(out.stats));
    writer.finish();
    return out;
}

nlohmann::json reconstructRecord(const ReconstructStatistics& s) {
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
            {"linear_residual", s.linearResidual},
            {"mean_shift_solve", s.solveMeanShift},
            {"mean_shift", s.meanShift},
            {"mean_scale", s.meanScale},
            {"mean_solves", s.meanSolves},
            {"mean_solver", s.meanSolver}};
}

file::StatTable reconstructTable(const ReconstructStatistics& s) {
    return file::valueTable("reconstruct", {{"norm", s.norm == "l1" ? 1.0 : 2.0},
                                            {"alpha", s.alpha},
                                            {"irls_iterations", double(s.irlsIterations)},
                                            {"solves", double(s.solves)},
                                            {"iterations", double(s.solverIterations)},
                                            {"linear_iterations", double(s.linearIterations)},
                                            {"initial_cost", s.initialCost},
                                            {"final_cost", s.finalCost},
                                            {"seconds", s.seconds},
                                            {"solver", s.solverUsed == PoissonSolver::Cgnr      ? 2.0
                                                       : s.solverUsed == PoissonSolver::EigenCg ? 3.0
                                                       : s.solverUsed == PoissonSolver::Cosine  ? 4.0
                                                                                                : 1.0},
                                            {"mean_shift_solve", s.solveMeanShift},
                                            {"mean_shift", s.meanShift},
                                            {"mean_scale", s.meanScale}});
}

std::string reconstructSummary(const ReconstructOutcome& outcome) {
    const ReconstructStatistics& s = outcome.stats;
    std::ostringstream o;
    o << s.norm << ", alpha " << s.alpha << ", " << outcome.width << "x" << outcome.height << ": "
      << (s.irlsIterations ? std::to_string(s.irlsIterations) + " IRLS steps, " : "") << s.solves << " solves with "
      << s.solver << " (" << s.solverReason << "), " << s.solverIterations << " iterations, " << s.linearIterations
      << " linear solver iterations";
    // The accuracy of Eigen CG or DCT, which measure it.
    if (s.solverUsed == PoissonSolver::EigenCg || s.solverUsed == PoissonSolver::Cosine)
        o << ", relative residual <= " << s.linearResidual;
    o << "; cost " << s.initialCost << " -> " << s.finalCost;
    // The mean against the primal's: what the minimizer did to it, and what the image has.
    const auto percent = [](double shift) {
        std::ostringstream p;
        p << std::showpos << std::fixed << std::setprecision(2) << 100 * shift << " %";
        return p.str();
    };
    o << "; mean " << percent(s.solveMeanShift) << " from the primal's";
    if (s.meanScale > 0)
        o << ", restored over " << s.meanScale << " px (" << s.meanSolves << " solves with " << s.meanSolver << ") to "
          << percent(s.meanShift);
    o << "; " << s.seconds << " s";
    return o.str();
}

} // namespace lt
