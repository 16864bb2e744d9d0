// lt-inspect: describe a scene or an lt file (paths or sample buffer): summary, vertex tables, OBJ
// polylines and histograms of paths.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <optional>
#include <span>
#include <sstream>
#include <type_traits>

#include "bsdf/bsdf.h"
#include "common/info.h"
#include "common/scene_options.h"
#include "common/tool.h"
#include "formats/ltfile.h"
#include "image/buffer_source.h"
#include "image/buffer_statistics.h"
#include "image/image_io.h"
#include "path/path_obj.h"
#include "path/path_statistics.h"
#include "math/constants.h"
#include "manifold/chains_in_path.h"
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
    for (const auto& [k, n] : m)
        s += (s.empty() ? "" : ", ") + k + " " + std::to_string(n);
    return s.empty() ? "none" : s;
}

std::string depthText(int d) { return d < 0 ? "unbounded" : std::to_string(d); }

nlohmann::json toJson(const lt::Scene& scene, const lt::SceneFeatures& f) {
    const auto& film = scene.camera.film();
    nlohmann::json j;
    j["kind"] = "scene";
    j["file"] = scene.filename;
    j["content_hash"] = lt::file::hashHex(scene.contentHash);
    j["shapes"] = {{"count", f.shapes},
                   {"by_type", f.shapeTypes},
                   {"triangles", f.triangles},
                   {"spheres", f.spheres},
                   {"disks", f.disks}};
    j["bsdfs"] = {{"by_kind", f.bsdfTypes},
                  {"delta", f.deltaBsdfs},
                  {"glossy", f.glossyBsdfs},
                  {"diffuse", f.diffuseBsdfs},
                  {"transmissive", f.transmissiveBsdfs},
                  {"min_glossy_roughness", f.minGlossyRoughness}};
    j["emitters"] = {{"count", scene.emitters.size()}, {"by_type", f.emitterTypes}};
    j["portals"] = f.portals;
    j["bounds"] = {{"min", {scene.bounds.lo.x, scene.bounds.lo.y, scene.bounds.lo.z}},
                   {"max", {scene.bounds.hi.x, scene.bounds.hi.y, scene.bounds.hi.z}},
                   {"diagonal", scene.bounds.diagonal()}};
    j["camera"] = {{"type", scene.camera.hasAperture() ? "thinlens" : "perspective"},
                   {"fov_x_degrees", scene.camera.fovX()},
                   {"aperture_radius", scene.camera.lens().apertureRadius},
                   {"focus_distance", scene.camera.hasAperture() ? nlohmann::json(scene.camera.lens().focusDistance)
                                                                 : nlohmann::json(nullptr)},
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
    auto row = [](const std::string& k, const std::string& v) {
        std::cout << std::left << std::setw(11) << k << v << '\n';
    };
    row("scene", scene.filename + "  (content hash " + lt::file::hashHex(scene.contentHash) + ")");
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
    cam << (scene.camera.hasAperture() ? "thinlens" : "perspective") << ", fov " << std::setprecision(4)
        << scene.camera.fovX() << " deg (horizontal), at " << fmt3(scene.camera.position()) << " looking "
        << fmt3(scene.camera.forward());
    if (scene.camera.hasAperture())
        cam << ", aperture radius " << scene.camera.lens().apertureRadius << " focused at "
            << scene.camera.lens().focusDistance;
    row("camera", cam.str());
    std::ostringstream fl;
    fl << film.width << " x " << film.height;
    if (film.cropWidth != film.width || film.cropHeight != film.height)
        fl << ", crop " << film.cropWidth << " x " << film.cropHeight << " at (" << film.cropX << ", " << film.cropY
           << ")";
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
        for (size_t i = 0; i < scene.ignoredHints.size(); ++i)
            std::cout << (i ? "; " : "") << scene.ignoredHints[i];
        std::cout << "  (rendering hints lt does not use)\n";
    }
    for (const auto& w : scene.warnings)
        std::cout << "warning    " << w << '\n';
}

// ---- lt files ---------------------------------------------------------------------------------

// A file is an lt file if it starts with the magic of formats/SPEC.md; anything else is a scene. Only
// these 4 bytes are looked at here: everything else goes through lt::file::Reader.
bool isLtFile(const std::string& path) {
    if (path == "-") return true;
    std::ifstream in(path, std::ios::binary);
    std::array<char, 4> magic{};
    return in.read(magic.data(), 4) && std::string(magic.data(), 4) == std::string("LTF\x01", 4);
}

std::string num(double v) {
    std::ostringstream s;
    s << std::setprecision(6) << v;
    return s.str();
}

template <class T, size_t N> std::string tuple(const std::array<T, N>& a) {
    std::string s = "(";
    for (size_t i = 0; i < N; ++i)
        s += (i ? ", " : "") + num(double(a[i]));
    return s + ")";
}

// A chain-state stream (lt-mutate --stream) in figures: its last round's, and the credit of all states (which
// sums to the mutations when every round was written).
struct ChainStreamSummary {
    uint64_t rounds = 0, states = 0, mutations = 0;
    double b = 0, credit = 0, wallSeconds = 0;
};
ChainStreamSummary chainStreamSummary(const std::vector<lt::file::ChainRound>& rounds) {
    ChainStreamSummary s;
    s.rounds = rounds.size();
    for (const auto& r : rounds) {
        s.states += r.states.size();
        for (const auto& st : r.states)
            s.credit += st.credit;
    }
    s.mutations = rounds.back().mutations;
    s.b = rounds.back().b;
    s.wallSeconds = rounds.back().wallSeconds;
    return s;
}

std::string kindText(lt::file::FileKind k) { return k == lt::file::FileKind::Paths ? "paths" : "buffer"; }

std::string vertexKindText(lt::file::VertexKind k) {
    switch (k) {
    case lt::file::VertexKind::Camera:
        return "camera";
    case lt::file::VertexKind::Light:
        return "light";
    case lt::file::VertexKind::Surface:
        return "surface";
    case lt::file::VertexKind::PortalCrossing:
        return "portal";
    }
    return "?";
}

// bsdf/bsdf.h Lobe bits: one of diffuse / glossy / delta, and R(eflection) or T(ransmission).
std::string lobeText(uint8_t lobe) {
    std::string s = lobe & lt::LobeDiffuse  ? "diffuse"
                    : lobe & lt::LobeGlossy ? "glossy"
                    : lobe & lt::LobeDelta  ? "delta"
                                            : "";
    if (lobe & lt::LobeReflection) s += s.empty() ? "R" : " R";
    if (lobe & lt::LobeTransmission) s += s.empty() ? "T" : " T";
    return s.empty() ? "-" : s;
}

std::string summaryText(const lt::Summary& s) {
    return "min " + num(s.min) + ", mean " + num(s.mean()) + ", max " + num(s.max);
}

std::string techniqueText(const std::pair<int, int>& st) {
    return "(" + std::to_string(st.first) + "," + std::to_string(st.second) + ")";
}

// Rows of cells as aligned columns: the first left-aligned (names), the others right-aligned (numbers).
void printTable(const std::vector<std::vector<std::string>>& rows, const std::string& indent) {
    std::vector<size_t> width;
    for (const auto& r : rows)
        for (size_t c = 0; c < r.size(); ++c) {
            if (width.size() <= c) width.push_back(0);
            width[c] = std::max(width[c], r[c].size());
        }
    for (const auto& r : rows) {
        std::cout << indent;
        for (size_t c = 0; c < r.size(); ++c)
            std::cout << (c ? "  " : "") << (c ? std::right : std::left) << std::setw(int(width[c])) << r[c];
        std::cout << '\n';
    }
}

void printBars(const std::string& title, const std::vector<std::pair<std::string, size_t>>& bars) {
    std::cout << title << '\n';
    size_t most = 1, label = 0;
    for (const auto& [k, n] : bars)
        most = std::max(most, n), label = std::max(label, k.size());
    for (const auto& [k, n] : bars)
        std::cout << "  " << std::right << std::setw(int(label)) << k << "  " << std::left << std::setw(40)
                  << std::string(size_t(std::ceil(40.0 * double(n) / double(most))), '#') << ' ' << n << '\n';
}

std::vector<std::pair<std::string, size_t>> lengthBars(const lt::PathStatistics& s) {
    std::vector<std::pair<std::string, size_t>> bars;
    for (const auto& [len, n] : s.lengths)
        bars.emplace_back(std::to_string(len), n);
    return bars;
}

std::vector<std::pair<std::string, size_t>> techniqueBars(const lt::PathStatistics& s) {
    std::vector<std::pair<std::string, size_t>> bars;
    for (const auto& [st, n] : s.techniques)
        bars.emplace_back(techniqueText(st), n);
    return bars;
}

std::string barsInline(const std::vector<std::pair<std::string, size_t>>& bars) {
    std::string s;
    for (const auto& [k, n] : bars)
        s += (s.empty() ? "" : ", ") + k + ": " + std::to_string(n);
    return s;
}

nlohmann::json summaryJson(const lt::Summary& s) { return {{"min", s.min}, {"mean", s.mean()}, {"max", s.max}}; }

nlohmann::json bufferJson(const lt::file::Buffer& b) {
    const lt::BufferStatistics st = lt::bufferStatistics(b);
    nlohmann::json channels = nlohmann::json::object();
    for (size_t c = 0; c < b.channels.size(); ++c)
        channels[b.channels[c]] = summaryJson(st.channels[c]);
    return {{"width", b.width},
            {"height", b.height},
            {"channels", b.channels},
            {"combine", b.combine},
            {"weight", b.weight},
            {"sample_counts", st.sampleCounts ? summaryJson(*st.sampleCounts) : nlohmann::json()},
            {"channel_stats", channels}};
}

nlohmann::json pathJson(size_t index, const lt::file::PathRecord& p) {
    nlohmann::json vertices = nlohmann::json::array();
    for (const auto& v : p.vertices)
        vertices.push_back({{"kind", vertexKindText(v.kind)},
                            {"lobe", v.lobe},
                            {"flags", v.flags},
                            {"shape", v.shape},
                            {"prim", v.prim},
                            {"coords", v.coords},
                            {"p", v.p},
                            {"ng", v.ng},
                            {"ns", v.ns},
                            {"bsdf", v.bsdf},
                            {"light", v.light},
                            {"roughness", v.roughness},
                            {"pdf_fwd", v.pdfFwd},
                            {"pdf_rev", v.pdfRev}});
    return {{"index", index},
            {"raster", p.raster},
            {"s", p.s},
            {"t", p.t},
            {"contribution", p.contribution},
            {"pdf", p.pdf},
            {"mis_weight", p.misWeight},
            {"weight", p.weight},
            {"rng_stream", p.rngStream},
            {"rng_offset", p.rngOffset},
            {"vertices", vertices}};
}

nlohmann::json fileJson(const lt::file::Content& f, std::optional<size_t> pathLimit) {
    const auto& c = f;
    nlohmann::json j;
    j["kind"] = kindText(c.kind);
    j["file"] = f.name;
    j["format_version"] = f.version;
    j["info"] = c.info;
    j["chunks"] = nlohmann::json::object();
    for (const auto& [tag, n] : f.chunkCounts)
        j["chunks"][tag] = n;
    j["buffers"] = nlohmann::json::array();
    for (const auto& b : c.buffers)
        j["buffers"].push_back(bufferJson(b));
    j["snapshots"] = nlohmann::json::array();
    for (const auto& s : c.snapshots)
        j["snapshots"].push_back({{"wall_seconds", s.wallSeconds},
                                  {"cpu_seconds", s.cpuSeconds},
                                  {"samples", s.samples},
                                  {"overhead_seconds", s.overheadSeconds},
                                  {"buffer", bufferJson(s.buffer)}});
    j["stats"] = nlohmann::json::array();
    for (const auto& t : c.stats)
        j["stats"].push_back({{"name", t.name}, {"columns", t.columns}, {"rows", t.rows}, {"values", t.values}});
    if (!c.rounds.empty()) {
        const ChainStreamSummary r = chainStreamSummary(c.rounds);
        j["chain_states"] = {{"rounds", r.rounds}, {"states", r.states}, {"mutations", r.mutations},
                             {"b", r.b},           {"credit", r.credit}, {"wall_seconds", r.wallSeconds}};
    }
    if (c.kind == lt::file::FileKind::Paths) {
        const lt::PathStatistics s = lt::pathStatistics(c.paths);
        nlohmann::json lengths = nlohmann::json::object(), techniques = nlohmann::json::object();
        for (const auto& [len, n] : s.lengths)
            lengths[std::to_string(len)] = n;
        for (const auto& [st, n] : s.techniques)
            techniques[techniqueText(st)] = n;
        j["paths"] = {{"count", s.count},
                      {"length_histogram", lengths},
                      {"technique_histogram", techniques},
                      {"weight", summaryJson(s.weight)}};
        if (pathLimit) {
            j["paths"]["records"] = nlohmann::json::array();
            for (size_t i = 0; i < std::min(*pathLimit, c.paths.size()); ++i)
                j["paths"]["records"].push_back(pathJson(i, c.paths[i]));
        }
    }
    return j;
}

void printBuffer(const std::string& label, const lt::file::Buffer& b) {
    const lt::BufferStatistics st = lt::bufferStatistics(b);
    std::string line = std::to_string(b.width) + " x " + std::to_string(b.height) + ", " +
                       std::to_string(b.channels.size()) + " channels, " + b.combine + ", weight " + num(b.weight);
    if (st.sampleCounts) line += ", samples per pixel " + summaryText(*st.sampleCounts);
    std::cout << std::left << std::setw(11) << label << line << '\n';
    std::vector<std::vector<std::string>> rows{{"channel", "min", "mean", "max"}};
    for (size_t c = 0; c < b.channels.size(); ++c)
        rows.push_back({b.channels[c], num(st.channels[c].min), num(st.channels[c].mean()), num(st.channels[c].max)});
    printTable(rows, "           ");
}

void printFile(const lt::file::Content& f, bool histogram) {
    const auto& c = f;
    const auto& info = c.info;
    auto row = [](const std::string& k, const std::string& v) {
        std::cout << std::left << std::setw(11) << k << v << '\n';
    };
    auto text = [&](const char* key) {
        return info.contains(key) && info[key].is_string() ? info[key].get<std::string>() : std::string();
    };
    row("file", f.name);
    row("kind", kindText(c.kind) + " file, format version " + std::to_string(f.version));
    std::string producer = text("producer").empty() ? "unknown" : text("producer");
    if (!text("version").empty()) producer += " " + text("version");
    if (info.contains("times") && info["times"].is_object() && info["times"].contains("start") &&
        info["times"]["start"].is_string())
        producer += ", started " + info["times"]["start"].get<std::string>();
    row("producer", producer);
    if (info.contains("command") && info["command"].is_array()) {
        std::string cmd;
        for (const auto& a : info["command"])
            cmd += (cmd.empty() ? "" : " ") + (a.is_string() ? a.get<std::string>() : a.dump());
        row("command", cmd);
    }
    if (info.contains("parameters") && info["parameters"].is_object()) {
        std::string params;
        for (const auto& [k, v] : info["parameters"].items())
            params += (params.empty() ? "" : ", ") + k + "=" + (v.is_string() ? v.get<std::string>() : v.dump());
        row("parameters", params);
    }
    if (info.contains("scene") && info["scene"].is_object())
        row("scene", info["scene"].value("path", std::string("?")) + "  (hash " +
                         info["scene"].value("hash", std::string("?")) + ")");
    std::string chunks;
    for (const auto& [tag, n] : f.chunkCounts)
        chunks += (chunks.empty() ? "" : ", ") + tag + " " + std::to_string(n);
    row("chunks", chunks);
    for (size_t i = 0; i < c.buffers.size(); ++i)
        printBuffer(c.buffers.size() > 1 ? "buffer " + std::to_string(i + 1) : "buffer", c.buffers[i]);
    if (!c.snapshots.empty())
        row("snapshots", std::to_string(c.snapshots.size()) + ", " + num(c.snapshots.front().wallSeconds) + " s to " +
                             num(c.snapshots.back().wallSeconds) + " s wall, " +
                             std::to_string(c.snapshots.front().samples) + " to " +
                             std::to_string(c.snapshots.back().samples) + " samples");
    for (const auto& t : c.stats) {
        std::cout << "stat       " << t.name << '\n';
        std::vector<std::vector<std::string>> rows{{""}};
        rows[0].insert(rows[0].end(), t.columns.begin(), t.columns.end());
        for (size_t r = 0; r < t.rows.size(); ++r) {
            rows.push_back({t.rows[r]});
            for (double v : t.values[r])
                rows.back().push_back(num(v));
        }
        printTable(rows, "           ");
    }
    if (!c.rounds.empty()) {
        const ChainStreamSummary r = chainStreamSummary(c.rounds);
        row("states", std::to_string(r.states) + " in " + std::to_string(r.rounds) + " rounds, " +
                          std::to_string(r.mutations) + " mutations, b = " + num(r.b) + ", credit " + num(r.credit) +
                          ", " + num(r.wallSeconds) + " s of chains (lt-gradient --from-paths)");
    }
    if (c.kind == lt::file::FileKind::Paths && (c.rounds.empty() || !c.paths.empty())) {
        const lt::PathStatistics s = lt::pathStatistics(c.paths);
        row("paths", std::to_string(s.count) + (s.count ? ", weight " + summaryText(s.weight) : ""));
        if (histogram) {
            printBars("path length (edges)", lengthBars(s));
            printBars("technique (s,t)", techniqueBars(s));
        } else if (s.count) {
            row("lengths", barsInline(lengthBars(s)) + "  (edges: paths)");
            row("techniques", barsInline(techniqueBars(s)) + "  ((s,t): paths)");
        }
    }
}

void printPaths(std::span<const lt::file::PathRecord> paths) {
    for (size_t i = 0; i < paths.size(); ++i) {
        const auto& p = paths[i];
        std::cout << "path " << i << ": raster " << tuple(p.raster) << ", s=" << p.s << " t=" << p.t
                  << ", contribution " << tuple(p.contribution) << ", MIS weight " << num(p.misWeight) << ", weight "
                  << num(p.weight) << '\n';
        std::vector<std::vector<std::string>> rows{
            {"#", "kind", "position", "ng", "ns", "shape/prim", "bsdf", "light", "lobe", "rough", "pdfFwd", "pdfRev"}};
        for (size_t k = 0; k < p.vertices.size(); ++k) {
            const auto& v = p.vertices[k];
            rows.push_back({std::to_string(k), vertexKindText(v.kind), tuple(v.p), tuple(v.ng), tuple(v.ns),
                            std::to_string(v.shape) + "/" + std::to_string(v.prim), std::to_string(v.bsdf),
                            std::to_string(v.light), lobeText(v.lobe), num(v.roughness), num(v.pdfFwd), num(v.pdfRev)});
        }
        printTable(rows, "  ");
    }
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"lt-inspect: describe a Mitsuba scene (its contents, what it needs: specular chains, glossy "
                 "surfaces, portals, environment light, and the rendering defaults it gives lt's tools) or an lt file "
                 "(kind, producer, parameters, scene, chunks, buffers, snapshots, statistics tables, paths).",
                 "lt-inspect"};
    std::string file, objOut, manifoldScene;
    bool json = false, paths = false, histogram = false, manifold = false;
    size_t limit = 0;
    std::vector<std::string> defines;
    app.add_option("FILE", file,
                   "a Mitsuba scene (.xml: 0.4-0.6, 2.x, 3.x), an lt file (.lts, .ltp; - for stdin) or an EXR image")
        ->required();
    app.add_flag("--json", json, "print a JSON object instead of text (for scripts)");
    app.add_option("-D,--define", defines, "scene parameter NAME=VALUE, overriding the scene's <default> values")
        ->type_name("NAME=VALUE");
    bool strict = false;
    lt::tool::addStrictFlag(app, strict);
    app.add_flag("--paths", paths, "paths file: print the vertex table of the first --limit paths");
    app.add_option("--limit", limit, "paths to show with --paths (default 10) or to write with --obj (default 10000)")
        ->check(lt::tool::PositiveNumber);
    app.add_option("--obj", objOut, "paths file: write the paths as OBJ polylines (light to eye), one object each");
    app.add_flag("--histogram", histogram, "paths file: show path length and technique histograms as bars");
    app.add_flag("--manifold", manifold,
                 "paths file: each path's specular chains, their generalized geometry terms and walks to themselves "
                 "(--limit paths listed, default 10), then the walk statistics of all paths");
    app.add_option("--scene", manifoldScene,
                   "with --manifold: the scene the paths were made from (default: the one named in the file's INFO; "
                   "its content hash must match)");
    return lt::tool::run(app, argc, argv, [&] {
        const bool fileOptions =
            paths || histogram || manifold || !objOut.empty() || !manifoldScene.empty() || app.count("--limit");
        if (lt::isExrFile(file)) {
            if (fileOptions || !defines.empty()) throw lt::Error(file + " is an EXR image: only --json applies");
            const lt::BufferSource s = lt::loadBuffer(file);
            if (json)
                std::cout
                    << nlohmann::json{{"kind", "exr"}, {"file", s.name}, {"buffers", {bufferJson(s.buffer)}}}.dump(2)
                    << '\n';
            else {
                std::cout << std::left << std::setw(11) << "file" << s.name << "\n"
                          << std::setw(11) << "kind"
                          << "EXR image\n";
                printBuffer("buffer", s.buffer);
            }
            return 0;
        }
        if (isLtFile(file)) {
            if (!defines.empty() && !manifold)
                throw lt::Error("-D applies to scenes (and to --manifold's scene); " + file + " is an lt file");
            if (!manifoldScene.empty() && !manifold) throw lt::Error("--scene goes with --manifold");
            const lt::file::Content f = lt::file::readAll(file);
            if ((paths || histogram || !objOut.empty()) && f.kind != lt::file::FileKind::Paths)
                throw lt::Error(f.name + ": --paths, --obj and --histogram need a paths file, this is a buffer file");
            if (manifold && f.kind != lt::file::FileKind::Paths)
                throw lt::Error(f.name + ": --manifold needs a paths file, this is a buffer file");
            const std::span<const lt::file::PathRecord> all(f.paths);
            if (manifold) {
                if (json) throw lt::Error("--manifold prints text only");
                const auto& info = f.info;
                const std::string scenePath = !manifoldScene.empty() ? manifoldScene
                                              : info.contains("scene") && info["scene"].is_object()
                                                  ? info["scene"].value("path", std::string())
                                                  : std::string();
                if (scenePath.empty()) throw lt::Error(f.name + ": names no scene; give it with --scene");
                const auto scene =
                    lt::loadScene(scenePath, lt::tool::parseDefines(defines), lt::tool::unknownProperties(strict));
                for (const auto& w : scene->warnings)
                    std::cerr << "lt-inspect: warning: " << w << '\n';
                lt::file::checkSceneHash(info, scene->contentHash, f.name, scenePath);
                lt::printManifoldReport(std::cout, *scene, all, limit ? limit : 10);
                return 0;
            }
            if (!objOut.empty())
                lt::writePathsObj(objOut, all.first(std::min(all.size(), limit ? limit : 10000)), f.name);
            const std::span<const lt::file::PathRecord> shown = all.first(std::min(all.size(), limit ? limit : 10));
            if (json) {
                std::cout << fileJson(f, paths ? std::optional(shown.size()) : std::nullopt).dump(2) << '\n';
            } else {
                printFile(f, histogram);
                if (paths) printPaths(shown);
            }
            return 0;
        }
        if (fileOptions)
            throw lt::Error("--paths, --limit, --obj, --histogram, --manifold and --scene apply to lt files; " + file +
                            " is not one");
        const auto scene = lt::loadScene(file, lt::tool::parseDefines(defines), lt::tool::unknownProperties(strict));
        const lt::SceneFeatures f = lt::analyzeScene(*scene);
        if (json)
            std::cout << toJson(*scene, f).dump(2) << '\n';
        else
            printText(*scene, f);
        return 0;
    });
}
