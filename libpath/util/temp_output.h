// An output file written under a temporary name beside its final one and renamed only when complete,
// so no half-written output ever carries the final name. For writers that open the file themselves
// (OpenImageIO, streams): they write to path(), then commit(). The temporary file is removed if
// commit() is never reached.
#pragma once

#include <string>

namespace lt {

// The temporary name of `finalPath` for this process: FINAL.partial-PID (formats/SPEC.md "Writing"), for
// lt's own files and for every other output alike.
[[nodiscard]] std::string temporaryName(const std::string& finalPath);

// Marks the open temporary file `fd` as being written (an exclusive flock, held until it is closed), so that
// removeStaleTemporaries never takes it, even from another host or PID namespace where its PID means nothing.
void lockAsWriting(int fd);

// Removes the FINAL.partial-PID files beside `finalPath` that a killed writer (SIGKILL, a crash, a power cut)
// left behind: those whose process no longer runs here and that no writer holds locked (lockAsWriting).
// Best effort: a file that cannot be removed is left alone.
void removeStaleTemporaries(const std::string& finalPath);

class TempOutput {
public:
    // Writes to temporaryName(finalPath), after removing the stale temporaries of earlier runs.
    explicit TempOutput(std::string finalPath);
    ~TempOutput();
    TempOutput(const TempOutput&) = delete;
    TempOutput& operator=(const TempOutput&) = delete;

    [[nodiscard]] const std::string& path() const { return temp_; } // where to write
    [[nodiscard]] const std::string& finalPath() const { return final_; }

    // Syncs the temporary file to disk and renames it to the final name; throws lt::Error naming the
    // final file (and removes the temporary file) if that fails.
    void commit();

private:
    std::string final_, temp_;
    int lock_ = -1; // the temporary file opened by us and locked as being written
    bool committed_ = false;
};

} // namespace lt
