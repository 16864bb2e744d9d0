#include "sampling/parallel_run.h"

namespace lt {

ParallelRun::ParallelRun(const RunControl& control)
    : control_(control), threads_(control.threads > 0 ? control.threads : tbb::this_task_arena::max_concurrency()),
      arena_(threads_), clock_(control.start) {}

void ParallelRun::forEach(uint64_t n, const std::function<void(uint64_t)>& work,
                          const std::function<void(uint64_t)>& merge) {
    uint64_t next = 0;
    ordered<uint64_t>(
        [&](uint64_t& i) {
            if (next >= n) return false;
            i = next++;
            return true;
        },
        [&](uint64_t& i) { work(i); }, [&](uint64_t& i) { merge(i); });
}

} // namespace lt
