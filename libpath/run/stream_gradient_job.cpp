#include "run/stream_gradient_job.h"

#include <iomanip>
#include <limits>
#include <sstream>

#include "run/run_summary.h"
#include "scene/scene.h"
#include "util/error.h"

namespace lt {

StreamGradientJob::StreamGradientJob(const Scene& scene, file::Reader& stream, const ChainStreamSettings& settings)
    : scene_(scene), stream_(stream), settings_(settings) {
    if (scene.camera.hasAperture())
        throw Error(scene.filename + ": the chain-state stream holds no lens points, and this scene's thinlens camera "
                                     "needs them (the gradient stage works with pinhole cameras)");
    file::checkSceneHash(stream.info(), scene.contentHash, stream.name(), scene.filename);
    const auto& made = stream.info().value("parameters", nlohmann::json::object());
    const Film& film = scene.camera.film();
    if (made.contains("resolution") && made["resolution"] != nlohmann::json{film.width, film.height})
        throw Error(stream.name() + ": made at resolution " + made["resolution"].dump() + " but the film is " +
                    std::to_string(film.width) + "x" + std::to_string(film.height) +
                    " (give the same --resolution to both tools)");
    // The chains left the direct part out (lt-mutate --direct-samples): this stage renders it, as lt-mutate would
    // with the same seed. Streams written before the split hold every path.
    if (const auto d = made.find("direct_samples"); d != made.end()) {
        if (!d->is_number_integer() || *d == 0 || *d < -1 || *d > std::numeric_limits<int>::max())
            throw Error(stream.name() + ": its direct_samples " + d->dump() + " is neither -1 nor a positive integer");
        settings_.direct.samples = d->get<int>();
    }
    if (const auto seed = made.find("seed"); seed != made.end() && seed->is_number_unsigned())
        settings_.seed = seed->get<uint64_t>();
    settings_.paths.rrDepth = scene.integrator.rrDepth;
}

nlohmann::json StreamGradientJob::parameters() const {
    return {{"method", "chain-states"},
            {"stream_producer", stream_.info().value("producer", "")},
            {"chain_parameters", stream_.info().value("parameters", nlohmann::json::object())},
            {"shift_threshold", settings_.shiftThreshold},
            {"direct_samples", settings_.direct.samples},
            {"weights", "pairs of a state and its shift, g*(x) / (g*(x) + g*(Tx) |T'|) with g* = lum f, each over the "
                        "chain's density b f*(x) / N"}};
}

StreamGradientOutcome StreamGradientJob::run(const RunControl& control) {
    StreamGradientOutcome out;
    ShiftStatistics shifts;
    out.stats = gradientsFromStream(scene_, stream_, settings_, out.image, shifts, control);
    const ChainStreamStats& s = out.stats;
    out.tables.push_back(
        runTable(s, {{"rounds", double(s.rounds)}, {"states", double(s.states)}, {"mutations", double(s.mutations)}},
                 {{"chain_wall_seconds", s.chainWallSeconds}, {"own_seconds", s.ownSeconds}}));
    out.tables.push_back(file::valueTable("normalization", {{"b", s.b}, {"b_samples", double(s.bSamples)}}));
    out.tables.push_back(shifts.table());
    const Film& film = scene_.camera.film();
    const double pixels = double(film.cropWidth) * double(film.cropHeight);
    std::ostringstream line;
    line << (s.interrupted ? "interrupted after " : "") << s.states << " chain states of " << s.rounds << " rounds ("
         << double(s.mutations) / pixels << " mutations/pixel) in " << formatSeconds(s.ownSeconds) << "; "
         << shifts.summary(false) << nonFiniteNote(s.health, "states");
    out.summary = line.str();
    return out;
}

} // namespace lt
