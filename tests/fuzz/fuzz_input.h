// What every libFuzzer harness shares. The readers under test take file names, as the tools give them, so
// each input is written to a file in a private directory first (a write of a few kilobytes that stays in the
// page cache, far cheaper than the parse) and read back through the very entry point a tool calls.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <zlib.h>

#include "util/error.h"

namespace lt::fuzz {

// Allocations the readers check against the memory available (util/memory_budget.h) are checked against
// 256 MiB here, well under libFuzzer's -rss_limit_mb (2048 in pipelines/fuzz.sh) with room for ASan's own: a
// file that declares more is refused as on a small machine, not reported as an out-of-memory finding, and no
// input spends the fuzzer's time clearing gigabytes.
inline const bool memoryLimited = setenv("LT_MEMORY_LIMIT", "256M", 0) == 0;

// A directory of this process only (mkdtemp under TMPDIR, named lt-fuzz-*), removed when the fuzzer ends
// normally; a crash, a timeout or an out-of-memory exit (libFuzzer's _Exit) leaves it behind.
class PrivateDirectory {
public:
    PrivateDirectory() {
        const char* tmp = std::getenv("TMPDIR");
        std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/lt-fuzz-XXXXXX";
        if (!mkdtemp(pattern.data())) std::abort();
        path_ = pattern;
    }
    ~PrivateDirectory() {
        std::error_code ignored;
        std::filesystem::remove_all(path_, ignored);
    }
    [[nodiscard]] const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
};

inline const std::filesystem::path& privateDirectory() {
    static const PrivateDirectory directory;
    return directory.path();
}

// Writes the input to NAME in the private directory and returns its path.
inline std::string writeInput(const uint8_t* data, size_t size, const std::string& name) {
    const std::filesystem::path path = privateDirectory() / name;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    if (!out.flush()) std::abort();
    return path.string();
}

// The input with every chunk's CRC made right (formats/SPEC.md: tag:char[4] length:u64 payload crc:u32 after
// a 12-byte header), so that mutated payloads get past the checksum to the parsers behind it; the harnesses
// of lt files read both the input as it is and this copy.
inline std::string withChunkChecksumsRecomputed(const uint8_t* data, size_t size) {
    std::string bytes(reinterpret_cast<const char*>(data), size);
    size_t at = 12;
    while (at + 12 <= bytes.size()) {
        uint64_t length = 0;
        std::memcpy(&length, bytes.data() + at + 4, 8); // little-endian, as the reader assumes
        if (length > bytes.size() - at - 12 || bytes.size() - at - 12 - length < 4) break;
        const auto* chunk = reinterpret_cast<const Bytef*>(bytes.data() + at);
        const uint32_t sum = static_cast<uint32_t>(crc32_z(0, chunk, 12 + length));
        std::memcpy(bytes.data() + at + 12 + length, &sum, 4);
        at += 12 + length + 4;
    }
    return bytes;
}

// Runs one read. lt::Error is the answer to bad input (one line naming the file); anything else escapes to
// libFuzzer, which reports it as a finding: a std::bad_alloc, an exception of a parser underneath that no
// check turned into a message, a crash, a sanitizer report, or a hang past -timeout.
template <class Read> void expectCleanRead(Read&& read) {
    try {
        read();
    } catch (const lt::Error&) {
    }
}

} // namespace lt::fuzz
