// The one reader and writer of lt's files (formats/SPEC.md gives the byte layout; formats/records.h the
// records). Every tool goes through these, so damage, truncation, version and scene mismatches are
// detected in one place and reported as one line naming the file, the chunk and what is wrong.
#pragma once

#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "formats/records.h"

namespace lt::file {

// The format version this lt writes and the newest it reads (SPEC.md "Versioning").
constexpr uint32_t kVersion = 1;

// Chain states as a CHST chunk holds them (SPEC.md), encoded where they arise: the Markov chains encode their
// own in parallel (lt-mutate --stream) and the writer only joins the pieces.
class EncodedChainStates {
public:
    void add(const ChainState& state);
    void clear() {
        bytes_.clear();
        count_ = 0;
    }
    [[nodiscard]] uint64_t count() const { return count_; }
    [[nodiscard]] const std::string& bytes() const { return bytes_; }

private:
    std::string bytes_;
    uint64_t count_ = 0;
};

// Writes one file chunk by chunk. On a path, the bytes go to NAME.partial-PID in the same directory and
// only finish() renames them to NAME, so no half-written output ever carries the final name; a writer
// destroyed before finish() removes its temporary file. On "-", chunks stream to stdout as they are
// written (a reader downstream can use them at once) and an unfinished stream simply lacks END!.
// Every error throws lt::Error naming the file.
class Writer {
public:
    // Writes the header and the INFO chunk (`info` must be a JSON object, see SPEC.md "INFO").
    Writer(const std::string& path, FileKind kind, const nlohmann::json& info);
    ~Writer();
    Writer(Writer&&) noexcept;
    Writer& operator=(Writer&&) noexcept;
    Writer(const Writer&) = delete;
    Writer& operator=(const Writer&) = delete;

    void writePaths(std::span<const PathRecord> paths);   // one PATH chunk; paths files only
    void writeChainRound(const ChainRound& round);        // one CHST chunk; paths files only
    // One CHST chunk of the round's figures (its `states` unused) and states already encoded, in the order given.
    void writeChainRound(const ChainRound& figures, std::span<const class EncodedChainStates* const> parts);
    void writeBuffer(const Buffer& buffer);               // one BUFR chunk; buffer files only
    void writeSnapshot(const Snapshot& snapshot);         // one SNAP chunk; buffer files only
    void writeStats(const StatTable& stats);              // one STAT chunk

    // Writes END!, flushes, fsyncs and (on a path) renames the temporary file to its final name.
    void finish();

    [[nodiscard]] const std::string& name() const;   // the final path, or "<stdout>"

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// The end marker: the file is complete.
struct End {};
// One decoded chunk. INFO is read when the Reader opens (Reader::info), unknown chunks are skipped.
using Chunk = std::variant<std::vector<PathRecord>, ChainRound, Buffer, Snapshot, StatTable, End>;

// Reads one file front to back without seeking, so "-" (stdin) and pipes work like files. Every
// length is checked against what the payload can hold before anything is allocated for it, and every
// chunk's CRC is checked, unknown ones included.
class Reader {
public:
    // Reads the header and the INFO chunk. With `expected`, a file of the other kind is an error.
    explicit Reader(const std::string& path, std::optional<FileKind> expected = std::nullopt);
    ~Reader();
    Reader(Reader&&) noexcept;
    Reader& operator=(Reader&&) noexcept;
    Reader(const Reader&) = delete;
    Reader& operator=(const Reader&) = delete;

    // The next known chunk; End once END! was read (and again on every later call).
    [[nodiscard]] Chunk next();

    [[nodiscard]] FileKind kind() const;
    [[nodiscard]] uint32_t version() const;
    [[nodiscard]] const nlohmann::json& info() const;
    [[nodiscard]] const std::string& name() const;   // the path, or "<stdin>"
    // Whether it reads a regular file (else a pipe or a terminal: a stream written while it is read).
    [[nodiscard]] bool regularFile() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// Everything one file holds, in file order within each kind.
struct Content {
    std::string name;     // the path, or "<stdin>"
    uint32_t version = 0; // the format version of the header
    FileKind kind = FileKind::Paths;
    nlohmann::json info;
    // Known chunks by tag (INFO and END! included) with their counts, in order of first appearance:
    // the file's table of contents for lt-inspect.
    std::vector<std::pair<std::string, size_t>> chunkCounts;
    std::vector<PathRecord> paths;   // all PATH batches concatenated
    std::vector<ChainRound> rounds;  // CHST chunks
    std::vector<Buffer> buffers;
    std::vector<Snapshot> snapshots;
    std::vector<StatTable> stats;
};

[[nodiscard]] Content readAll(const std::string& path, std::optional<FileKind> expected = std::nullopt);

// A STAT table of named figures in one column "value" (SPEC.md: the "run", "normalization" and
// "reconstruct" tables), rows in the given order.
[[nodiscard]] StatTable valueTable(std::string name, const std::vector<std::pair<std::string, double>>& rows);

// The scene hash as INFO stores it: 16 lowercase hex digits.
[[nodiscard]] std::string hashHex(uint64_t hash);

// Throws "FILE: made for scene X (hash a) but the scene given is Y (hash b)" unless INFO's
// "scene": {"path", "hash"} carries `sceneHash`; a file without a scene hash is an error too.
// `scenePath` (the scene the user gave) only makes the message clearer.
void checkSceneHash(const nlohmann::json& info, uint64_t sceneHash, const std::string& file,
                    const std::string& scenePath = "");

} // namespace lt::file
