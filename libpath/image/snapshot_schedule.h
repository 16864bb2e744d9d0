// When a render tool writes progress snapshots (issue 4 "Error against run time"): at wall-clock
// times (a list, or a doubling series) or at sample counts. One mechanism for every render tool; the
// tools parse the option with parse() and ask due() at their natural boundaries (a complete pass over
// the image for the pixel samplers), so every snapshot is a consistent, normalized estimate.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace lt {

class SnapshotSchedule {
public:
    SnapshotSchedule() = default;
    // "doubling" (1, 2, 4, 8 ... s), "doubling:START" (START, 2 START, ...), or "T1,T2,..." seconds in
    // increasing order. Throws lt::Error with the offending text otherwise.
    static SnapshotSchedule parseTimes(const std::string& spec);
    // "N1,N2,..." samples per pixel (or mutations per pixel), increasing.
    static SnapshotSchedule parseSamples(const std::string& spec);

    [[nodiscard]] bool enabled() const { return kind_ != Kind::None; }
    // Whether a snapshot is due at this boundary (wall seconds of rendering so far, samples per pixel so
    // far); advances past every point it covers, so a slow pass produces one snapshot, not several.
    [[nodiscard]] bool due(double seconds, double samplesPerPixel);

private:
    enum class Kind { None, Times, Doubling, Samples };
    Kind kind_ = Kind::None;
    std::vector<double> points_;
    size_t next_ = 0;
    double doubling_ = 1;
};

} // namespace lt
