#include "sampling/run_clock.h"

#include <ctime>

#include "formats/ltfile.h"
#include "scene/accel.h"

namespace lt {

namespace {
// Process CPU time: all threads of the run together.
double processCpuSeconds() { return double(std::clock()) / CLOCKS_PER_SEC; }
} // namespace

RunStart RunStart::now() { return {std::chrono::steady_clock::now(), processCpuSeconds(), EmbreeAccel::rayCount()}; }

RunClock::RunClock(std::optional<RunStart> start) : start_(start.value_or(RunStart::now())) {}

double RunClock::wallSeconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_.wall).count() - snapshotSeconds_;
}

double RunClock::cpuSeconds() const { return processCpuSeconds() - start_.cpuSeconds; }

RunProgress RunClock::progress(const char* phase, double fraction, uint64_t samples, uint64_t totalSamples) const {
    RunProgress p;
    p.phase = phase;
    p.fraction = fraction;
    p.samples = samples;
    p.totalSamples = totalSamples;
    p.wallSeconds = wallSeconds();
    p.cpuSeconds = cpuSeconds();
    p.snapshotSeconds = snapshotSeconds_;
    return p;
}

void RunClock::snapshot(const RunSnapshotCallback& write, const RunProgress& progress,
                        const std::function<file::Buffer()>& develop, RunRecord& record) {
    const auto t0 = std::chrono::steady_clock::now();
    write(progress, develop());
    ++record.snapshots;
    snapshotSeconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

file::StatTable runTable(const RunRecord& record, std::vector<std::pair<std::string, double>> counts,
                         const std::vector<std::pair<std::string, double>>& times) {
    counts.insert(counts.end(), {{"wall_seconds", record.wallSeconds}, {"cpu_seconds", record.cpuSeconds}});
    counts.insert(counts.end(), times.begin(), times.end());
    counts.insert(counts.end(), {{"rays", double(record.rays)},
                                 {"nonfinite_dropped", double(record.health.nonFinite)},
                                 {"interrupted", record.interrupted ? 1.0 : 0.0},
                                 {"snapshots", double(record.snapshots)},
                                 {"snapshot_seconds", record.snapshotSeconds}});
    return file::valueTable("run", counts);
}

void RunClock::close(RunRecord& record) const {
    record.wallSeconds = wallSeconds();
    record.cpuSeconds = cpuSeconds();
    record.snapshotSeconds = snapshotSeconds_;
    record.rays = EmbreeAccel::rayCount() - start_.rays;
}

} // namespace lt
