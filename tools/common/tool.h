// What every lt-* main() shares: the one-line error convention and exit codes. Header-only so each
// tool stays a single thin translation unit.
#pragma once

#include <CLI/CLI.hpp>

#include <exception>
#include <functional>
#include <iostream>
#include <string>

#include "math/error.h"

namespace lt::tool {

// Run a tool body; lt::Error and other exceptions become one line "TOOL: error: MESSAGE" on stderr
// and exit code 1; command-line errors are CLI11's (exit code 105 and its message), --help exits 0.
inline int run(CLI::App& app, int argc, char** argv, const std::function<int()>& body) {
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    try {
        return body();
    } catch (const std::exception& e) {
        std::cerr << app.get_name() << ": error: " << e.what() << '\n';
        return 1;
    }
}

} // namespace lt::tool
