// Checking a large allocation against the memory the machine has before making it: one clear error
// naming what needed the memory, instead of std::bad_alloc or the kernel's OOM killer halfway through a
// run.
#pragma once

#include <cstdint>
#include <string>

namespace lt {

// Bytes of memory available to a new allocation: MemAvailable of /proc/meminfo (free memory plus what the
// kernel can reclaim), or the free physical pages where that file is missing; 0 when neither is known.
[[nodiscard]] uint64_t availableMemory();

// Throws lt::Error "WHAT needs X GiB of memory, more than the Y GiB available" when `bytes` exceeds the
// available memory (nothing is checked when it is unknown). `bytes` is a double so that products of sizes
// cannot overflow before the check.
void requireMemory(double bytes, const std::string& what);

} // namespace lt
