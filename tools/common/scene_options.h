// Scene options several tools share: loading with -D parameters, --resolution, --strict, and the loader's
// warnings.
#pragma once

#include <CLI/CLI.hpp>

#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "common/info.h"
#include "util/error.h"
#include "scene/scene.h"

namespace lt::tool {

// --strict: a scene property lt does not read stops the load (naming file and line) instead of a warning.
inline void addStrictFlag(CLI::App& app, bool& strict) {
    app.add_flag("--strict", strict,
                 "stop at a scene property lt does not read (default: warn once per plugin and property and ignore "
                 "it, as Mitsuba does)");
}

inline UnknownProperties unknownProperties(bool strict) {
    return strict ? UnknownProperties::Fail : UnknownProperties::Warn;
}

// Load SCENE with its -D NAME=VALUE parameters and an optional "WxH" film size (the horizontal field of
// view is kept); print the loader's warnings unless quiet.
inline std::unique_ptr<Scene> loadSceneWithOptions(const std::string& tool, const std::string& path,
                                                   const std::vector<std::string>& defines,
                                                   const std::string& resolution, bool strict, bool quiet) {
    auto scene = loadScene(path, parseDefines(defines), unknownProperties(strict));
    if (!resolution.empty()) {
        int w = 0, h = 0;
        char x = 0, rest = 0;
        std::istringstream in(resolution);
        if (!(in >> w >> x >> h) || x != 'x' || w < 1 || h < 1 || (in >> rest))
            throw Error("--resolution expects WxH with positive integers, got '" + resolution + "'");
        scene->camera = scene->camera.withResolution(w, h);
    }
    for (const auto& w : scene->warnings)
        if (!quiet) std::cerr << tool << ": warning: " << w << '\n';
    return scene;
}

} // namespace lt::tool
