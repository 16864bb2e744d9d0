#include "bsdf/ior_presets.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <utility>

#include "util/error.h"

namespace lt {

namespace {

// Mitsuba 0.5 values at 589 nm (sodium D line). "glass" is ours: the common scene-file word, taken as
// BK7, Mitsuba's default intIOR.
constexpr std::array<std::pair<std::string_view, double>, 24> Iors{{
    {"vacuum", 1.0},          {"helium", 1.000036},       {"hydrogen", 1.000132},
    {"air", 1.000277},        {"carbon dioxide", 1.00045}, {"water", 1.3330},
    {"acetone", 1.36},        {"ethanol", 1.361},         {"carbon tetrachloride", 1.461},
    {"glycerol", 1.4729},     {"benzene", 1.501},         {"silicone oil", 1.52045},
    {"bromine", 1.661},       {"water ice", 1.31},        {"fused quartz", 1.458},
    {"pyrex", 1.470},         {"acrylic glass", 1.49},    {"polypropylene", 1.49},
    {"bk7", 1.5046},          {"sodium chloride", 1.544}, {"amber", 1.55},
    {"pet", 1.5750},          {"diamond", 2.419},         {"glass", 1.5046},
}};

} // namespace

std::optional<double> lookupIor(std::string_view name) {
    std::string lower(name);
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    for (const auto& [n, value] : Iors)
        if (n == lower) return value;
    return std::nullopt;
}

std::vector<std::string> iorPresetNames() {
    std::vector<std::string> names;
    for (const auto& [n, value] : Iors) names.emplace_back(n);
    return names;
}

void checkIorPair(const std::string& plugin, double intIOR, double extIOR) {
    if (!(intIOR > 0) || !(extIOR > 0) || !std::isfinite(intIOR) || !std::isfinite(extIOR))
        throw Error(plugin + ": intIOR and extIOR must be positive and finite (got " + std::to_string(intIOR) + ", " +
                    std::to_string(extIOR) + ")");
}

} // namespace lt
