#include "gradient/gradient_settings.h"

#include <iomanip>
#include <sstream>
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

std::string ShiftStatistics::summary(bool roulette) const {
    const double n = std::max<double>(1, double(shifts));
    std::ostringstream out;
    out << uint64_t(shifts) << std::setprecision(3)
        << " shifts: " << 100 * double(causes[size_t(ShiftCause::Reconnected)]) / n << "% reconnected, "
        << 100 * double(causes[size_t(ShiftCause::Mismatch)]) / n << "% mismatched, "
        << 100 * double(causes[size_t(ShiftCause::Occluded)]) / n << "% occluded";
    if (roulette)
        out << "; " << 100 * double(rrSurvived) / std::max<double>(1, double(rrTested))
            << "% of base paths survived Russian roulette";
    return out.str();
}

OptionSpec shiftThresholdOption() {
    return {"--shift-threshold",
            "shift_threshold",
            "Beckmann roughness at or below which a vertex is followed by its half vector instead of reconnected "
            "(default 0.001, as the public G-PT code)",
            "FLOAT:NONNEGATIVE",
            "0.001",
            option::nonNegative()};
}

std::vector<OptionSpec> pathReusingOptions() {
    return {{"--tile", "tile",
             "gdpr: tile size T; every base path is reused by the (T+1) x (T+1) pixels around its tile (default 6, the "
             "paper's; 6 to 8 are the most efficient there)",
             "INT:1..64", "6", option::integer(1, 64)},
            {"--rr-delta", "rr_delta",
             "gdpr: base paths survive with probability min(1, max(q_min, luminance / delta)) (default 0.1)",
             "FLOAT:POSITIVE", "0.1", option::positive()},
            {"--rr-min", "rr_min", "gdpr: q_min, the least survival probability (default 0.1; 0 is biased)",
             "FLOAT:0..1", "0.1", option::number([](double v) { return v >= 0 && v <= 1; }, "must lie in [0, 1]")}};
}

GradientSettings gradientSettings(const PathSettings& paths, const OptionValues& values) {
    GradientSettings gs;
    gs.paths = paths;
    gs.shiftThreshold = values.number("shift_threshold");
    if (values.has("tile")) gs.tile = values.at("tile").get<int>();
    if (values.has("rr_delta")) gs.rrDelta = values.number("rr_delta");
    if (values.has("rr_min")) gs.rrMin = values.number("rr_min");
    return gs;
}

nlohmann::json gradientRecord() {
    return {{"mis", "balance over the pixels' techniques, light and BSDF sample within each"}};
}

} // namespace lt
