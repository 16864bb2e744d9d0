#include "math/memory_budget.h"

#include <unistd.h>

#include <cstdio>
#include <fstream>

#include "math/error.h"

namespace lt {

uint64_t availableMemory() {
    std::ifstream meminfo("/proc/meminfo");
    for (std::string line; std::getline(meminfo, line);) {
        unsigned long long kib = 0;
        if (std::sscanf(line.c_str(), "MemAvailable: %llu kB", &kib) == 1) return uint64_t(kib) * 1024;
    }
    const long pages = sysconf(_SC_AVPHYS_PAGES), pageSize = sysconf(_SC_PAGESIZE);
    return pages > 0 && pageSize > 0 ? uint64_t(pages) * uint64_t(pageSize) : 0;
}

void requireMemory(double bytes, const std::string& what) {
    const uint64_t available = availableMemory();
    if (available == 0 || !(bytes > double(available))) return;
    const auto gib = [](double b) {
        char text[32];
        std::snprintf(text, sizeof text, "%.3g", b / double(uint64_t(1) << 30));
        return std::string(text);
    };
    throw Error(what + " needs " + gib(bytes) + " GiB of memory, more than the " + gib(double(available)) +
                " GiB available");
}

} // namespace lt
