// Named indices of refraction for the dielectric parameters (intIOR / extIOR of dielectric,
// thindielectric, roughdielectric, plastic, roughplastic; extEta of the conductors).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace lt {

// Mitsuba 0.5's table (documentation Table 3, util lookupIOR), case-insensitive, plus "glass" as an
// alias of "bk7". Nothing when the name is unknown.
[[nodiscard]] std::optional<double> lookupIor(std::string_view name);
[[nodiscard]] std::vector<std::string> iorPresetNames();

// Validation shared by the BSDFs with a dielectric interface: both indices positive and finite;
// throws lt::Error naming the plugin otherwise.
void checkIorPair(const std::string& plugin, double intIOR, double extIOR);

} // namespace lt
