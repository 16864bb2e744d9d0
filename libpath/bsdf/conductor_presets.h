// Mitsuba 0.5's named conductors (the `material` parameter of conductor and roughconductor) as the
// RGB complex index eta + i k that Mitsuba's RGB mode produces from its spectral data.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "math/spectrum.h"

namespace lt {

struct ConductorIor {
    Spectrum eta, k;
};

// The preset of that name (Mitsuba's spelling, e.g. "Cu", "a-C", "Na_palik"); nothing if unknown.
[[nodiscard]] std::optional<ConductorIor> lookupConductor(std::string_view name);
// All known names, for the loader's error message.
[[nodiscard]] std::vector<std::string> conductorPresetNames();

} // namespace lt
