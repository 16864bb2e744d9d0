#include "gradient/gradient_settings.h"

#include <string>

#include "formats/ltfile.h"

namespace lt {

void ShiftStatistics::add(const ShiftOutcome& o) {
    ++shifts;
    ++causes[size_t(o.cause)];
    if (o.cause == ShiftCause::Reconnected) ++reconnectDepth[size_t(std::min(o.reconnectDepth, MaxDepth + 1) - 1)];
}

file::StatTable ShiftStatistics::table() const {
    static const char* names[] = {"reconnected", "followed", "no_primary_hit", "mismatch",
                                  "occluded",    "refraction", "escaped",       "early_out"};
    static_assert(std::size(names) == size_t(ShiftCause::Count));
    std::vector<std::pair<std::string, double>> rows = {{"base_paths", double(basePaths)}, {"shifts", double(shifts)}};
    for (size_t c = 0; c < size_t(ShiftCause::Count); ++c)
        rows.emplace_back(names[c], double(causes[c]));
    for (int d = 0; d <= MaxDepth; ++d)
        rows.emplace_back("reconnect_depth_" + std::to_string(d + 1) + (d == MaxDepth ? "+" : ""),
                          double(reconnectDepth[size_t(d)]));
    rows.emplace_back("rr_tested", double(rrTested));
    rows.emplace_back("rr_survived", double(rrSurvived));
    return file::valueTable("shift", rows);
}

} // namespace lt
