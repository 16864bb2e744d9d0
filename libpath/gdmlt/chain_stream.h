// The gradient stage of gradient-domain MLT (lt-gradient --from-paths): reads a chain-state stream
// (lt-mutate --stream, formats/SPEC.md "CHST") round by round and estimates the primal image, its forward
// differences and the directly seen emitters from the chains' states (gdmlt/chain_gradient.h), read with
// b / N as the stream stood after each round. States are processed in parallel in blocks and merged in stream
// order, so the result does not depend on the thread count.
#pragma once

#include <atomic>
#include <chrono>
#include <optional>

#include "formats/ltfile.h"
#include "gradient/gradient_settings.h"
#include "image/snapshot_schedule.h"
#include "sampling/direct_split.h"
#include "sampling/parallel_run.h"

namespace lt {

class Scene;

struct ChainStreamSettings {
    double shiftThreshold = 0.001;
    SnapshotSchedule snapshots;
    // The direct part, when the chains left it out (the stream's lt-mutate --direct-samples): rendered into the
    // plane "direct" before the rounds are read (sampling/direct_split.h), with Russian roulette and MIS from
    // `paths`, seeded from `seed`.
    DirectSplit direct{-1};
    PathSettings paths;
    uint64_t seed = 0;
};

// Times: what the image cost when its snapshot (or the end) is written. Read from a pipe (lt-mutate --stream - |
// lt-gradient --from-paths -), the stages run side by side and started together: the wall seconds are those
// since the pipeline began (RunControl::start: the tool's start, since in a pipe every stage starts at once and
// this one waits for the others' output), the CPU seconds the chains' (the round's figures in the
// stream) plus this process's. Read from a file written before, the stages ran one after the other: the chains' wall
// and CPU seconds plus this stage's own work on the rounds so far (time spent reading left out).
struct ChainStreamStats : RunRecord {
    uint64_t rounds = 0, states = 0, mutations = 0;
    double b = 0;
    uint64_t bSamples = 0;
    double chainWallSeconds = 0, chainCpuSeconds = 0; // of the last round read
    double ownSeconds = 0;                            // this stage's work
};

// Reads `stream` to its END! (or until `stop`) and writes the planes primal, dx, dy, direct into `result` (direct: the
// chains' paths of one edge, or with a direct split the direct part).
// Throws lt::Error naming the stream for a state that does not fit the scene, a stream without rounds, or
// damage (the reader's).
ChainStreamStats gradientsFromStream(const Scene& scene, file::Reader& stream, const ChainStreamSettings& settings,
                                     file::Buffer& result, ShiftStatistics& shifts, const RunControl& control);

} // namespace lt
