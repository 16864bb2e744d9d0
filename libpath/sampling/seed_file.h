// The seed file: what `lt-seed --paths` hands to the path-space Markov chains, written and read here
// only (lt-seed writes it, lt-mutate and the tests read it). Its PATH chunks hold draws made in
// proportion to the paths' weights, so a chain starts from one picked uniformly (Veach and Guibas 1997,
// start-up bias); its STAT "normalization" table holds b, the integral of the chains' target f* over the
// image, with the number of camera samples it was estimated from (so that samples drawn later can be
// pooled with it), the candidates offered and the draws kept. The format itself is formats/SPEC.md.
#pragma once

#include <cstdint>
#include <vector>

#include "formats/ltfile.h"
#include "sampling/seed_reservoir.h"

namespace lt {

struct SeedFile {
    std::vector<file::PathRecord> paths; // draws in proportion to weight; a path may appear repeatedly
    double b = 0;                        // the seed run's estimate of the integral of f* over the image
    uint64_t samples = 0;                // camera samples that estimate came from
    int minEdges = 1; // the paths and b leave out shorter paths (the direct split; files without the row: 1)
};

// Writes the reservoir's draws and the normalization table of a run of `samples` camera samples over
// `pixels` pixels, then finishes the file. Returns b and the number of draws written.
struct SeedFileWritten {
    double b = 0;
    size_t kept = 0;
};
SeedFileWritten writeSeedFile(file::Writer& writer, const SeedReservoir& reservoir, uint64_t samples, double pixels);

// The seed file read by file::readAll; throws lt::Error naming the file when b or the sample count is
// missing or not a finite number, and when its paths do not fit chains of paths from `minEdges` edges on (seeds
// with or without the paths of the direct part, sampling/direct_split.h, for chains of the other kind).
[[nodiscard]] SeedFile readSeedFile(file::Content&& content, int minEdges);

} // namespace lt
