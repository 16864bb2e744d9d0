// Checking a large allocation against the memory the machine has before making it: one clear error
// naming what needed the memory, instead of std::bad_alloc or the kernel's OOM killer halfway through a
// run.
#pragma once

#include <cstdint>
#include <string>

namespace lt {

// Bytes of memory available to a new allocation: MemAvailable of /proc/meminfo (free memory plus what the
// kernel can reclaim), or the free physical pages where that file is missing, and no more than a cgroup v2
// memory limit leaves (a container's), nor than the environment variable LT_MEMORY_LIMIT (bytes, or with the
// suffix K, M, G or T; a malformed value is an error); 0 when none is known. Swap is not counted.
[[nodiscard]] uint64_t availableMemory();

// Throws lt::Error "WHAT needs X GiB of memory, more than the Y GiB available" (MiB, KiB or bytes for less) when
// `bytes` exceeds the available memory (nothing is checked when it is unknown). `bytes` is a double so that products of
// sizes cannot overflow before the check.
void requireMemory(double bytes, const std::string& what);

} // namespace lt
