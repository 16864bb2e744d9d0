// The INFO object every tool writes (formats/SPEC.md): who made the file, how, and from which scene.
#pragma once

#include <nlohmann/json.hpp>

#include <ctime>
#include <string>
#include <utility>
#include <vector>

#include "formats/ltfile.h"
#include "util/error.h"
#include "scene/scene.h"

namespace lt::tool {

inline nlohmann::json makeInfo(const std::string& producer, int argc, char** argv, const nlohmann::json& parameters,
                               const Scene* scene) {
    nlohmann::json info;
    info["producer"] = producer;
    info["version"] = LT_VERSION;
    info["command"] = std::vector<std::string>(argv, argv + argc);
    info["parameters"] = parameters;
    if (parameters.contains("seed")) info["seed"] = parameters["seed"];
    if (scene) info["scene"] = {{"path", scene->filename}, {"hash", file::hashHex(scene->contentHash)}};
    char date[64];
    const std::time_t now = std::time(nullptr);
    std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
    info["times"] = {{"start", date}};
    return info;
}

// -D NAME=VALUE scene parameters.
inline std::map<std::string, std::string> parseDefines(const std::vector<std::string>& defines) {
    std::map<std::string, std::string> params;
    for (const auto& d : defines) {
        const auto eq = d.find('=');
        if (eq == std::string::npos || eq == 0) throw Error("-D expects NAME=VALUE, got '" + d + "'");
        params[d.substr(0, eq)] = d.substr(eq + 1);
    }
    return params;
}

} // namespace lt::tool
