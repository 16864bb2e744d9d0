#include "math/memory_budget.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <optional>

#include "math/error.h"

namespace lt {

namespace {

// The one number a file such as /sys/fs/cgroup/memory.max holds; nothing when missing or "max".
std::optional<uint64_t> numberIn(const char* file) {
    std::ifstream in(file);
    unsigned long long value = 0;
    if (!(in >> value)) return std::nullopt;
    return uint64_t(value);
}

} // namespace

uint64_t availableMemory() {
    uint64_t available = 0;
    std::ifstream meminfo("/proc/meminfo");
    for (std::string line; std::getline(meminfo, line);) {
        unsigned long long kib = 0;
        if (std::sscanf(line.c_str(), "MemAvailable: %llu kB", &kib) == 1) available = uint64_t(kib) * 1024;
    }
    if (available == 0) {
        const long pages = sysconf(_SC_AVPHYS_PAGES), pageSize = sysconf(_SC_PAGESIZE);
        if (pages > 0 && pageSize > 0) available = uint64_t(pages) * uint64_t(pageSize);
    }
    // In a container (cgroup v2) the limit is the container's, which /proc/meminfo does not show.
    const auto limit = numberIn("/sys/fs/cgroup/memory.max"), used = numberIn("/sys/fs/cgroup/memory.current");
    if (limit && used) {
        const uint64_t left = *limit > *used ? *limit - *used : 0;
        available = available > 0 ? std::min(available, left) : left;
    }
    return available;
}

void requireMemory(double bytes, const std::string& what) {
    const uint64_t available = availableMemory();
    if (available == 0 || !(bytes > double(available))) return;
    const auto gib = [](double b) {
        char text[32];
        std::snprintf(text, sizeof text, "%.1f", b / double(uint64_t(1) << 30));
        return std::string(text);
    };
    throw Error(what + " needs " + gib(bytes) + " GiB of memory, more than the " + gib(double(available)) +
                " GiB available");
}

} // namespace lt
