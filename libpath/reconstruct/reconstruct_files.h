// What lt-reconstruct does between reading its options and printing its line: read a gradient-domain render (an
// lt buffer file, a multi-layer EXR, or separate layers), reconstruct it (screened_poisson.h) and write the image
// (EXR by the output's extension, an lt buffer file otherwise). From an lt buffer file to an lt buffer file the
// input is streamed and every progress snapshot reconstructed on the way, its times increased by its
// reconstruction's (what the image cost), so that lt-error measures reconstructed images against time.
#pragma once

#include <nlohmann/json.hpp>

#include <atomic>
#include <string>

#include "formats/records.h"
#include "reconstruct/screened_poisson.h"

namespace lt {

// Where the render comes from: IN, or the layers apart (--primal, --dx, --dy, optionally --direct).
struct ReconstructInputs {
    std::string input;
    std::string primal, dx, dy, direct;
};

struct ReconstructOutcome {
    ReconstructStatistics stats; // of the final image's reconstruction
    uint32_t width = 0, height = 0;
    bool interrupted = false; // a stop cut a streamed input short: its newest buffer was reconstructed
};

// Whether reconstructFiles streams the input (an lt buffer file into an lt buffer file): then a stop cuts it short
// and keeps what was read; otherwise there is one image, and nothing to cut.
[[nodiscard]] bool streamsInput(const ReconstructInputs& inputs, const std::string& output);

// Reconstructs and writes `output`, whose INFO (or EXR header) records `info` with the input's name and scene.
// `stop` is asked between the chunks of a streamed input. Throws lt::Error naming the file for a bad input.
ReconstructOutcome reconstructFiles(const ReconstructInputs& inputs, const std::string& output,
                                    const ReconstructSettings& settings, nlohmann::json info,
                                    const ReconstructProgress& progress, const std::atomic<bool>* stop);

// The STAT table "reconstruct" (formats/SPEC.md): numbers only, so the norm is its exponent (1 or 2) and the solver
// a code (1 Ceres sparse normal Cholesky, 2 Ceres CGNR, 3 Eigen CG, 4 DCT).
[[nodiscard]] file::StatTable reconstructTable(const ReconstructStatistics& s);
// The same figures for INFO, with the norm and solver as names.
[[nodiscard]] nlohmann::json reconstructRecord(const ReconstructStatistics& s);
// One line for the user: norm, size, solves, iterations, cost, time.
[[nodiscard]] std::string reconstructSummary(const ReconstructOutcome& outcome);

} // namespace lt
