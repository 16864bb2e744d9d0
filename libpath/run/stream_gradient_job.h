// What lt-gradient --from-paths does between reading its options and writing its files: the gradient stage of
// gradient-domain MLT (gdmlt/chain_stream.h) on a chain-state stream, with the checks that the stream belongs to
// the scene and the film, and the tables and line that report it.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "formats/ltfile.h"
#include "gdmlt/chain_stream.h"

namespace lt {

struct StreamGradientOutcome {
    ChainStreamStats stats;
    file::Buffer image;                  // primal, dx, dy, direct
    std::vector<file::StatTable> tables; // "run", "normalization", "shift"
    std::string summary;                 // for the user
};

class StreamGradientJob {
public:
    // Throws lt::Error when the stream was made for another scene or film size, or the camera needs lens points.
    StreamGradientJob(const Scene& scene, file::Reader& stream, const ChainStreamSettings& settings);
    // What the output records of the run besides the options every render tool shares and the stream's name.
    [[nodiscard]] nlohmann::json parameters() const;
    [[nodiscard]] StreamGradientOutcome run(const RunControl& control);

private:
    const Scene& scene_;
    file::Reader& stream_;
    ChainStreamSettings settings_;
};

} // namespace lt
