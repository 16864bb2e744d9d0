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
#include "util/option_spec.h"

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

// A CLI11 check that runs one of the library's option parsers (util/option_spec.h: the one reading and check of
// a value, with its words for what is wrong), so the options of the tools and those of the registries are refused
// alike. `name` is what --help shows after the type.
inline CLI::Validator optionCheck(const std::string& name, std::function<nlohmann::json(const std::string&)> parse) {
    return {[parse = std::move(parse)](std::string& text) -> std::string {
                try {
                    (void)parse(text);
                    return {};
                } catch (const Error& e) {
                    return e.what();
                }
            },
            name};
}

// Checks for numeric options. CLI11's own PositiveNumber and NonNegativeNumber (2.1) answer "not in range
// 0.000000 to" followed by the largest double written out in 309 digits; these say what is wrong in words.
inline const CLI::Validator PositiveNumber = optionCheck("POSITIVE", option::positive());
inline const CLI::Validator NonNegativeNumber = optionCheck("NONNEGATIVE", option::nonNegative());
// --threads: 0 means all cores; more than MaxThreads workers is a typo, not a machine.
inline constexpr int MaxThreads = 1024;
inline const CLI::Validator ThreadCount =
    optionCheck("0.." + std::to_string(MaxThreads),
                option::number([](double v) { return v >= 0 && v <= MaxThreads && v == std::floor(v); },
                               "must be a whole number from 0 (all cores) to " + std::to_string(MaxThreads)));

} // namespace lt::tool
