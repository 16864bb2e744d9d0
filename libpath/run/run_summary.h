// How the runs speak of themselves in words, the same way in every tool: times, and the samples dropped for not
// being finite numbers.
#pragma once

#include <sstream>
#include <string>

#include "path/sample_health.h"

namespace lt {

// "0.25 s", "3.10 s", "42 s": precision for short times, none for long ones.
[[nodiscard]] inline std::string formatSeconds(double s) {
    std::ostringstream o;
    o.precision(s < 10 ? 2 : 0);
    o << std::fixed << s << " s";
    return o.str();
}

// " (3 non-finite samples dropped)" with `what` "samples", or nothing when none was.
[[nodiscard]] inline std::string nonFiniteNote(const SampleHealth& health, const std::string& what) {
    if (!health.nonFinite) return {};
    return " (" + std::to_string(health.nonFinite) + " non-finite " + what + " dropped)";
}

} // namespace lt
