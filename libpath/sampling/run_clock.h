// What every render run shares, whatever produces its samples (the pixel render loop of BDPT and path
// tracing, the Markov-chain runner): its clock, the progress it reports, the snapshots it writes and the
// record of how it went.
//
// The clock runs from the run's start (which a tool may set earlier, so that work done ahead of the loop,
// such as a Markov chain's own BDPT seeding, counts) and leaves out the time spent writing snapshots:
// error-against-time curves then measure rendering, not file output, and each snapshot stores the time
// it left out.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "formats/records.h"
#include "path/sample_health.h"

namespace lt {

struct RunProgress {
    const char* phase = "";     // what the run is doing: "render", "start-up", "chains"
    double fraction = -1;       // of the run, when known
    uint64_t samples = 0;       // merged so far: camera samples, or mutations of the chains
    uint64_t totalSamples = 0;  // expected in all (0 when only a time limit bounds the run)
    int passesDone = 0;         // pixel render loop: complete passes (one sample per pixel each)
    double wallSeconds = 0;     // since the start, snapshot writing excluded
    double cpuSeconds = 0;      // process CPU time since the start
    double snapshotSeconds = 0; // wall time spent writing snapshots so far
    double b = 0;               // Markov chains: the normalization the image is read with at this moment
};

using RunProgressCallback = std::function<void(const RunProgress&)>;
// A snapshot: the image as it stands (a complete, normalized estimate), with the progress it belongs to.
using RunSnapshotCallback = std::function<void(const RunProgress&, const file::Buffer&)>;

// How a run went: the part of the statistics every run has.
struct RunRecord {
    double wallSeconds = 0, cpuSeconds = 0; // as RunProgress
    uint64_t rays = 0;                      // rays traced (closest hit and shadow)
    SampleHealth health;
    bool interrupted = false; // stopped by Ctrl-C (or SIGTERM) before its end
    int snapshots = 0;
    double snapshotSeconds = 0;
};

// The "run" STAT table of a run's output (formats/SPEC.md): `counts`, what this kind of run counted (samples,
// mutations, ...), its wall and CPU seconds, `times`, the times of its parts (a start-up's), then what every run
// records besides: its rays, dropped samples, interruption and snapshots.
[[nodiscard]] file::StatTable runTable(const RunRecord& record, std::vector<std::pair<std::string, double>> counts,
                                       const std::vector<std::pair<std::string, double>>& times = {});

// When a run began, on each of its counters: wall time, the process's CPU time and the rays traced so far.
struct RunStart {
    std::chrono::steady_clock::time_point wall;
    double cpuSeconds = 0;
    uint64_t rays = 0;
    [[nodiscard]] static RunStart now();
};

class RunClock {
public:
    // `start`: when the run began; empty: now.
    explicit RunClock(std::optional<RunStart> start = std::nullopt);

    [[nodiscard]] double wallSeconds() const; // snapshot writing excluded
    [[nodiscard]] double cpuSeconds() const;
    [[nodiscard]] double snapshotSeconds() const { return snapshotSeconds_; }

    // A progress record with the clock's times filled in.
    [[nodiscard]] RunProgress progress(const char* phase, double fraction, uint64_t samples,
                                       uint64_t totalSamples) const;
    // Hands the image `develop` makes to `write`, keeping the time both take out of the run's wall time;
    // counts the snapshot in `record`.
    void snapshot(const RunSnapshotCallback& write, const RunProgress& progress,
                  const std::function<file::Buffer()>& develop, RunRecord& record);
    // The times, snapshot counts and rays of the run so far, into `record`.
    void close(RunRecord& record) const;

private:
    RunStart start_;
    double snapshotSeconds_ = 0;
};

} // namespace lt
