#include "util/memory_budget.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>

#include "util/error.h"
#include "util/number_text.h"

namespace lt {

namespace {

// The one number a file such as /sys/fs/cgroup/memory.max holds; nothing when missing or "max".
std::optional<uint64_t> numberIn(const char* file) {
    std::ifstream in(file);
    unsigned long long value = 0;
    if (!(in >> value)) return std::nullopt;
    return uint64_t(value);
}

// LT_MEMORY_LIMIT: bytes, or a number with the suffix K, M, G or T (powers of 1024); nothing when unset.
std::optional<uint64_t> userMemoryLimit() {
    const char* env = std::getenv("LT_MEMORY_LIMIT");
    if (!env || !*env) return std::nullopt;
    std::string text = env;
    while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back())))
        text.pop_back();
    double unit = 1;
    if (const char last = text.empty() ? '\0' : char(std::toupper(static_cast<unsigned char>(text.back())));
        last == 'K' || last == 'M' || last == 'G' || last == 'T') {
        unit = std::pow(1024.0, last == 'K' ? 1 : last == 'M' ? 2 : last == 'G' ? 3 : 4);
        text.pop_back();
    }
    // At least one byte: a limit of 0 would read as "unknown" and turn every check off.
    const double bytes = numberFromText(text).value_or(0) * unit;
    if (!(bytes >= 1) || !(bytes < 1.8e19))
        throw Error("LT_MEMORY_LIMIT: '" + std::string(env) + "' is not a memory size such as 4G, 512M or 1000000");
    return uint64_t(bytes);
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
    // A limit the user sets for lt alone (a shared machine, a fuzzer's memory bound).
    if (const auto limit = userMemoryLimit()) available = available > 0 ? std::min(available, *limit) : *limit;
    return available;
}

void requireMemory(double bytes, const std::string& what) {
    const uint64_t available = availableMemory();
    if (available == 0 || !(bytes > double(available))) return;
    const auto size = [](double b) { // "1.5 GiB", "95 MiB", "12 KiB" or "100 bytes"
        char text[32];
        if (b >= double(uint64_t(1) << 30))
            std::snprintf(text, sizeof text, "%.1f GiB", b / double(uint64_t(1) << 30));
        else if (b >= double(uint64_t(1) << 20))
            std::snprintf(text, sizeof text, "%.0f MiB", b / double(uint64_t(1) << 20));
        else if (b >= 1024)
            std::snprintf(text, sizeof text, "%.0f KiB", b / 1024);
        else
            std::snprintf(text, sizeof text, "%.0f bytes", b);
        return std::string(text);
    };
    throw Error(what + " needs " + size(bytes) + " of memory, more than the " + size(double(available)) + " available");
}

} // namespace lt
