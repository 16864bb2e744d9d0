// The one parallel loop of every run (the pixel render loop, the Markov chains' rounds, their start-ups, the
// gradient stage of gradient-domain MLT), with what a run around it shares: its threads, its clock
// (sampling/run_clock.h), the stop flag of Ctrl-C, its progress and its snapshots.
//
// Determinism: work items are issued one after another in a fixed order, worked on by the run's threads in
// parallel, and merged strictly in issue order (a TBB pipeline with serial in-order first and last stages), so
// whatever the merge sums (a film's floats, a reservoir's draws, an estimate's samples) comes out the same for
// every thread count. After each item its thread adds the rays it traced to the run's count (scene/accel.h).
#pragma once

#include <oneapi/tbb/parallel_pipeline.h>
#include <oneapi/tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "sampling/run_clock.h"
#include "scene/accel.h"

namespace lt {

// What a caller (a tool) gives a run: its threads, when it began, how to stop it, and what to do with its
// progress and snapshots.
struct RunControl {
    RunControl() = default;
    explicit RunControl(int threads_, RunSnapshotCallback snapshot_ = {})
        : threads(threads_), snapshot(std::move(snapshot_)) {}

    int threads = 0; // 0 = all cores
    // When the run began, for its clock, time limit and ray count: set it before work done ahead of the run (a
    // Markov chain's own BDPT seeding, the direct part of the image, a pipeline's earlier stage) so that it counts;
    // empty: when the run starts.
    std::optional<RunStart> start;
    const std::atomic<bool>* stop = nullptr; // Ctrl-C: the run ends at its next item and keeps what it merged
    RunProgressCallback progress;
    RunSnapshotCallback snapshot;
    std::function<void(const std::string&)> note; // a line for the user as the run goes on (its seeding, say)
};

class ParallelRun {
public:
    explicit ParallelRun(const RunControl& control);

    [[nodiscard]] int threads() const { return threads_; }
    [[nodiscard]] RunClock& clock() { return clock_; }
    [[nodiscard]] const RunClock& clock() const { return clock_; }
    [[nodiscard]] double elapsed() const { return clock_.wallSeconds(); }
    [[nodiscard]] bool stopped() const { return control_.stop && control_.stop->load(); }
    [[nodiscard]] bool snapshots() const { return bool(control_.snapshot); }

    // Hands a progress record to the caller.
    void report(const RunProgress& progress) const {
        if (control_.progress) control_.progress(progress);
    }
    // A snapshot of the image `develop` makes, its time kept out of the run's (RunClock::snapshot).
    void snapshot(const RunProgress& progress, const std::function<file::Buffer()>& develop, RunRecord& record) {
        clock_.snapshot(control_.snapshot, progress, develop, record);
    }

    // The loop: `issue` fills the next item and returns true, or returns false to end the loop (it runs alone, in
    // order, and decides when the run stops: a count reached, the clock, stopped()); `work` runs on any thread;
    // `merge` sees the items strictly in issue order. An exception of any stage ends the loop and reaches the caller.
    template <class Item>
    void ordered(const std::function<bool(Item&)>& issue, const std::function<void(Item&)>& work,
                 const std::function<void(Item&)>& merge);
    // Items 0 .. n-1, all of them (a caller that may stop asks stopped() between such loops): work(i) in
    // parallel, merge(i) in order of i.
    void forEach(uint64_t n, const std::function<void(uint64_t)>& work, const std::function<void(uint64_t)>& merge);
    // `f` on the run's threads (for work that parallelises itself, such as a film's merge of splats).
    template <class F> void execute(F&& f) { arena_.execute(std::forward<F>(f)); }

private:
    RunControl control_;
    int threads_;
    tbb::task_arena arena_;
    RunClock clock_;
};

template <class Item>
void ParallelRun::ordered(const std::function<bool(Item&)>& issue, const std::function<void(Item&)>& work,
                          const std::function<void(Item&)>& merge) {
    // oneTBB hands a token back only after the last stage's body has returned, and that stage takes the items in
    // issue order: when item k is issued at most tokens - 1 items are in flight, all after item k - tokens, whose
    // slot it therefore reuses. `tokens` slots hold every item, and nothing is left allocated when a stage throws.
    // A reused slot holds its last item's values: `issue` and `work` set every field they read.
    const size_t tokens = size_t(2 * threads_ + 2);
    std::vector<Item> slots(tokens);
    uint64_t issued = 0;
    arena_.execute([&] {
        tbb::parallel_pipeline(
            tokens,
            tbb::make_filter<void, Item*>(tbb::filter_mode::serial_in_order, [&](tbb::flow_control& fc) -> Item* {
                Item* item = &slots[issued % tokens];
                if (!issue(*item)) {
                    fc.stop();
                    return nullptr;
                }
                ++issued;
                return item;
            }) & tbb::make_filter<Item*, Item*>(tbb::filter_mode::parallel, [&](Item* item) {
                work(*item);
                EmbreeAccel::flushRayCount();
                return item;
            }) & tbb::make_filter<Item*, void>(tbb::filter_mode::serial_in_order, [&](Item* item) { merge(*item); }));
    });
}

} // namespace lt
