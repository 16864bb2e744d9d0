// lt-inspect: describe a scene (and, once the file formats exist, any lt file).
#include <nlohmann/json.hpp>

#include <cstdio>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

#include "common/tool.h"
#include "math/constants.h"
#include "scene/scene.h"
#include "scene/scene_features.h"

namespace {

std::string fmt3(const lt::Vec3& v) {
    std::ostringstream s;
    s << std::setprecision(4) << '(' << v.x << ", " << v.y << ", " << v.z << ')';
    return s.str();
}

std::string counts(const std::map<std::string, size_t>& m) {
    std::string s;
    for (const auto& [k, n] : m) s += (s.empty() ? "" : ", ") + k + " " + std::to_string(n);
    return s.empty() ? "none" : s;
}

std::string depthText(int d) { return d < 0 ? "unbounded" : std::to_string(d); }

std::string hashText(uint64_t h) {
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
    return buf;
}

nlohmann::json toJson(const lt::Scene& scene, const lt::SceneFeatures& f) {
    const auto& film = scene.camera.film();
    nlohmann::json j;
    j["kind"] = "scene";
    j["file"] = scene.filename;
    j["content_hash"] = hashText(scene.contentHash);
    j["shapes"] = {{"count", f.shapes}, {"by_type", f.shapeTypes}, {"triangles", f.triangles},
                   {"spheres", f.spheres}, {"disks", f.disks}};
    j["bsdfs"] = {{"by_kind", f.bsdfTypes}, {"delta", f.deltaBsdfs}, {"glossy", f.glossyBsdfs},
                  {"diffuse", f.diffuseBsdfs}, {"transmissive", f.transmissiveBsdfs},
                  {"min_glossy_roughness", f.minGlossyRoughness}};
    j["emitters"] = {{"count", scene.emitters.size()}, {"by_type", f.emitterTypes}};
    j["portals"] = f.portals;
    j["bounds"] = {{"min", {scene.bounds.lo.x, scene.bounds.lo.y, scene.bounds.lo.z}},
                   {"max", {scene.bounds.hi.x, scene.bounds.hi.y, scene.bounds.hi.z}},
                   {"diagonal", scene.bounds.diagonal()}};
    j["camera"] = {{"type", "perspective"},
                   {"fov_x_degrees", scene.camera.fovX()},
                   {"position", {scene.camera.position().x, scene.camera.position().y, scene.camera.position().z}},
                   {"forward", {scene.camera.forward().x, scene.camera.forward().y, scene.camera.forward().z}}};
    j["film"] = {{"type", film.type},
                 {"width", film.width},
                 {"height", film.height},
                 {"crop", {film.cropX, film.cropY, film.cropWidth, film.cropHeight}},
                 {"filter", film.filter.name()},
                 {"filter_radius", film.filter.radius}};
    j["render_defaults"] = {{"integrator", scene.integrator.type},
                            {"max_depth", scene.integrator.maxDepth},
                            {"rr_depth", scene.integrator.rrDepth},
                            {"spp", scene.integrator.sampleCount}};
    auto need = [](bool v, const std::string& why) { return nlohmann::json{{"value", v}, {"reason", why}}; };
    j["needs"] = {{"specular_chains", need(f.specularChains, f.specularReason)},
                  {"glossy_surfaces", need(f.glossySurfaces, f.glossyReason)},
                  {"portals", need(f.hasPortals, f.portalReason)},
                  {"environment_light", need(f.environmentLight, f.environmentReason)},
                  {"delta_lights", need(f.deltaLights, f.deltaLightReason)}};
    j["ignored_hints"] = scene.ignoredHints;
    j["warnings"] = scene.warnings;
    return j;
}

void printText(const lt::Scene& scene, const lt::SceneFeatures& f) {
    const auto& film = scene.camera.film();
    auto row = [](const std::string& k, const std::string& v) { std::cout << std::left << std::setw(11) << k << v << '\n'; };
    row("scene", scene.filename + "  (content hash " + hashText(scene.contentHash) + ")");
    row("shapes", std::to_string(f.shapes) + ": " + counts(f.shapeTypes));
    row("triangles", std::to_string(f.triangles) + (f.spheres || f.disks
                                                        ? "  (+ " + std::to_string(f.spheres) + " analytic spheres, " +
                                                              std::to_string(f.disks) + " disks)"
                                                        : ""));
    row("bsdfs", counts(f.bsdfTypes));
    row("emitters", std::to_string(scene.emitters.size()) + ": " + counts(f.emitterTypes));
    row("portals", std::to_string(f.portals));
    row("bounds", fmt3(scene.bounds.lo) + " to " + fmt3(scene.bounds.hi) + ", diagonal " +
                      std::to_string(scene.bounds.diagonal()));
    std::ostringstream cam;
    cam << "perspective, fov " << std::setprecision(4) << scene.camera.fovX() << " deg (horizontal), at "
        << fmt3(scene.camera.position()) << " looking " << fmt3(scene.camera.forward());
    row("camera", cam.str());
    std::ostringstream fl;
    fl << film.width << " x " << film.height;
    if (film.cropWidth != film.width || film.cropHeight != film.height)
        fl << ", crop " << film.cropWidth << " x " << film.cropHeight << " at (" << film.cropX << ", " << film.cropY << ")";
    fl << ", " << film.filter.name() << " filter (radius " << film.filter.radius << " px)";
    row("film", fl.str());
    row("defaults", std::to_string(scene.integrator.sampleCount) + " spp, maxDepth " +
                        depthText(scene.integrator.maxDepth) + ", rrDepth " + std::to_string(scene.integrator.rrDepth) +
                        " (from the scene's " + scene.integrator.type + " integrator and sampler)");
    std::cout << "needs\n";
    auto need = [](const std::string& k, bool v, const std::string& why) {
        std::cout << "  " << std::left << std::setw(19) << k << std::setw(5) << (v ? "yes" : "no") << why << '\n';
    };
    need("specular chains", f.specularChains, f.specularReason);
    need("glossy surfaces", f.glossySurfaces, f.glossyReason);
    need("portals", f.hasPortals, f.portalReason);
    need("environment light", f.environmentLight, f.environmentReason);
    need("delta lights", f.deltaLights, f.deltaLightReason);
    if (!scene.ignoredHints.empty()) {
        std::cout << "ignored    ";
        for (size_t i = 0; i < scene.ignoredHints.size(); ++i) std::cout << (i ? "; " : "") << scene.ignoredHints[i];
        std::cout << "  (rendering hints lt does not use)\n";
    }
    for (const auto& w : scene.warnings) std::cout << "warning    " << w << '\n';
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"lt-inspect: describe a Mitsuba scene: its contents, what it needs (specular chains, glossy "
                 "surfaces, portals, environment light) and the rendering defaults it gives lt's tools.",
                 "lt-inspect"};
    std::string file;
    bool json = false;
    std::vector<std::string> defines;
    app.add_option("FILE", file, "a Mitsuba 0.5/0.6 scene (.xml)")->required();
    app.add_flag("--json", json, "print a JSON object instead of text (for scripts)");
    app.add_option("-D,--define", defines, "scene parameter NAME=VALUE, overriding the scene's <default> values")
        ->type_name("NAME=VALUE");
    return lt::tool::run(app, argc, argv, [&] {
        std::map<std::string, std::string> params;
        for (const auto& d : defines) {
            const auto eq = d.find('=');
            if (eq == std::string::npos || eq == 0) throw lt::Error("-D expects NAME=VALUE, got '" + d + "'");
            params[d.substr(0, eq)] = d.substr(eq + 1);
        }
        const auto scene = lt::loadScene(file, params);
        const lt::SceneFeatures f = lt::analyzeScene(*scene);
        if (json) std::cout << toJson(*scene, f).dump(2) << '\n';
        else printText(*scene, f);
        return 0;
    });
}
