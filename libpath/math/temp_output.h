// An output file written under a temporary name beside its final one and renamed only when complete,
// so no half-written output ever carries the final name. For writers that open the file themselves
// (OpenImageIO, streams): they write to path(), then commit(). The temporary file is removed if
// commit() is never reached.
#pragma once

#include <string>

namespace lt {

class TempOutput {
public:
    // The temporary name is FINAL.partial-PID, as for lt's own files (formats/SPEC.md "Writing").
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
    bool committed_ = false;
};

} // namespace lt
