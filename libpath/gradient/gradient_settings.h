// The settings of the gradient-domain estimators (lt-gradient): how base paths are sampled, how the shift
// classifies vertices, and gradient-domain path reusing's tiles and Russian roulette ([GDPR] Sec. 3.3, 4).
#pragma once

#include <array>
#include <atomic>
#include <cstdint>

#include "formats/records.h"
#include "gradient/shift_mapping.h"
#include "sampling/path_settings.h"
#include "util/option_spec.h"

namespace lt {

struct GradientSettings {
    PathSettings paths;            // the base paths' length bound and Russian roulette
    double shiftThreshold = 0.001; // roughness at or below which a vertex is not connectable
    int tile = 6;                  // path reusing: tile size T (tiles of T x T, traced as (T+1) x (T+1))
    double rrDelta = 0.1;          // path reusing: base paths survive with min(1, max(rrMin, lum / rrDelta))
    double rrMin = 0.1;
};

// The options of the gradient-domain estimators: the shift's threshold (both), path reusing's tile and Russian
// roulette (gdpr).
[[nodiscard]] OptionSpec shiftThresholdOption();
[[nodiscard]] std::vector<OptionSpec> pathReusingOptions();
// The settings of their values (those not given keep GradientSettings' defaults).
[[nodiscard]] GradientSettings gradientSettings(const PathSettings& paths, const OptionValues& values);
// What the gradient-domain estimators record of how they weigh their samples.
[[nodiscard]] nlohmann::json gradientRecord();

// What the shifts did, counted across threads (sums do not depend on the order).
struct ShiftStatistics {
    static constexpr int MaxDepth = 8; // reconnection depths 1 .. 8, and deeper together
    std::atomic<uint64_t> basePaths{0}, shifts{0}, rrTested{0}, rrSurvived{0};
    std::array<std::atomic<uint64_t>, size_t(ShiftCause::Count)> causes{};
    std::array<std::atomic<uint64_t>, MaxDepth + 1> reconnectDepth{};

    void add(const ShiftOutcome& o);
    // STAT table "shift" (one column "value"): base_paths, shifts, one row per cause (reconnected, followed,
    // no_primary_hit, mismatch, occluded, refraction, escaped, early_out), reconnect_depth_1 .. _8 and
    // reconnect_depth_9+,
    // rr_tested and rr_survived.
    [[nodiscard]] file::StatTable table() const;
    // "N shifts: x% reconnected, y% mismatched, z% occluded", and with `roulette` the share of base paths that
    // survived Russian roulette.
    [[nodiscard]] std::string summary(bool roulette) const;
};

} // namespace lt
