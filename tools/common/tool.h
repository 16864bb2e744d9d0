// What every lt-* main() shares: the one-line error convention and exit codes. Header-only so each
// tool stays a single thin translation unit.
#pragma once

#include <CLI/CLI.hpp>

#include <cmath>
#include <exception>
#include <functional>
#include <iostream>
#include <optional>
#include <string>

#include "util/error.h"
#include "util/number_text.h"

namespace lt::tool {

// Run a tool body; lt::Error and other exceptions become one line "TOOL: error: MESSAGE" on stderr
// and exit code 1; command-line errors the same one line with CLI11's exit code (105 for a bad value),
// --help exits 0.
inline int run(CLI::App& app, int argc, char** argv, const std::function<int()>& body) {
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);
        std::cerr << app.get_name() << ": error: " << e.what() << " (--help lists the options)\n";
        return e.get_exit_code();
    }
    try {
        return body();
    } catch (const std::exception& e) {
        std::cerr << app.get_name() << ": error: " << e.what() << '\n';
        return 1;
    }
}

namespace detail {

// The value of a numeric option's text, or nothing when it is not one finite number (nan, inf, 1x).
inline std::optional<double> parseNumber(const std::string& text) {
    const std::optional<double> v = numberFromText(text);
    if (!v || !std::isfinite(*v)) return std::nullopt;
    return v;
}

inline CLI::Validator numberCheck(const std::string& name, const std::function<bool(double)>& ok,
                                  const std::string& what) {
    return {[ok, what](std::string& text) -> std::string {
                const auto v = parseNumber(text);
                return v && ok(*v) ? std::string() : what + ", got " + text;
            },
            name};
}

} // namespace detail

// Checks for numeric options. CLI11's own PositiveNumber and NonNegativeNumber (2.1) answer "not in range
// 0.000000 to" followed by the largest double written out in 309 digits; these say what is wrong in words.
inline const CLI::Validator PositiveNumber =
    detail::numberCheck("POSITIVE", [](double v) { return v > 0; }, "must be a positive number");
inline const CLI::Validator NonNegativeNumber =
    detail::numberCheck("NONNEGATIVE", [](double v) { return v >= 0; }, "must be a number >= 0");
// --threads: 0 means all cores; more than MaxThreads workers is a typo, not a machine.
inline constexpr int MaxThreads = 1024;
inline const CLI::Validator ThreadCount = detail::numberCheck(
    "0.." + std::to_string(MaxThreads), [](double v) { return v >= 0 && v <= MaxThreads && v == std::floor(v); },
    "must be a whole number from 0 (all cores) to " + std::to_string(MaxThreads));

} // namespace lt::tool
