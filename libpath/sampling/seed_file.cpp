#include "sampling/seed_file.h"

#include <algorithm>
#include <cmath>
#include <span>

#include "util/error.h"

namespace lt {

namespace {
constexpr const char* TableName = "normalization";
constexpr size_t PathsPerChunk = 4096;
} // namespace

SeedFileWritten writeSeedFile(file::Writer& writer, const SeedReservoir& reservoir, uint64_t samples, double pixels) {
    const double b = reservoir.normalization(samples, pixels);
    const auto draws = reservoir.draws();
    for (size_t i = 0; i < draws.size(); i += PathsPerChunk)
        writer.writePaths(std::span(draws).subspan(i, std::min(PathsPerChunk, draws.size() - i)));
    writer.writeStats(file::valueTable(TableName, {{"b", b},
                                                   {"samples", double(samples)},
                                                   {"candidates", double(reservoir.candidates())},
                                                   {"kept", double(draws.size())},
                                                   {"min_edges", double(reservoir.minEdges())}}));
    writer.finish();
    return {b, draws.size()};
}

SeedFile readSeedFile(file::Content&& content, int minEdges) {
    double b = -1, samples = -1, seedMinEdges = 1;
    for (const auto& t : content.stats)
        if (t.name == TableName)
            for (size_t r = 0; r < t.rows.size(); ++r) {
                if (t.values[r].empty()) continue;
                if (t.rows[r] == "b") b = t.values[r][0];
                if (t.rows[r] == "samples") samples = t.values[r][0];
                if (t.rows[r] == "min_edges") seedMinEdges = t.values[r][0];
            }
    if (!(b >= 0) || !std::isfinite(b))
        throw Error(content.name + ": no normalization b (STAT \"normalization\"); was it written by lt-seed --paths?");
    if (!(samples >= 1) || !std::isfinite(samples))
        throw Error(content.name + ": no sample count of the seed run (STAT \"normalization\" row \"samples\")");
    if (!(samples < 9.2e18)) // beyond uint64_t: a damaged file, not a run
        throw Error(content.name + ": the seed run's sample count " + std::to_string(samples) + " is out of range");
    if (seedMinEdges != double(minEdges)) {
        const auto kind = [](double edges) {
            return edges > 1 ? std::string("leave out the paths of the direct part (lt-seed --direct-split on)")
                             : std::string("hold paths of every length (lt-seed --direct-split off)");
        };
        throw Error(content.name + ": its seed paths and b " + kind(seedMinEdges) + ", but this run's chains " +
                    (minEdges > 1 ? "leave the direct part to --direct-samples" : "render every path (--direct-samples -1)") +
                    ": make the seeds with lt-seed --direct-split " + (minEdges > 1 ? "on" : "off"));
    }
    return {std::move(content.paths), b, uint64_t(samples), minEdges};
}

} // namespace lt
