// Scene options several tools share: loading with -D parameters, --resolution, and the loader's warnings.
#pragma once

#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "common/info.h"
#include "math/error.h"
#include "scene/scene.h"

namespace lt::tool {

// Load SCENE with its -D NAME=VALUE parameters and an optional "WxH" film size (the horizontal field of
// view is kept); print the loader's warnings unless quiet.
inline std::unique_ptr<Scene> loadSceneWithOptions(const std::string& tool, const std::string& path,
                                                   const std::vector<std::string>& defines,
                                                   const std::string& resolution, bool quiet) {
    auto scene = loadScene(path, parseDefines(defines));
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
