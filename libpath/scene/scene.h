// A loaded scene: shapes, materials, emitters, the sensor, and the acceleration structure over them.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bsdf/bsdf.h"
#include "math/distribution.h"
#include "scene/accel.h"
#include "scene/camera.h"
#include "scene/emitter.h"
#include "scene/emitters/scene_disk.h"
#include "scene/shape.h"

namespace lt {

// Rendering defaults read from the scene's integrator and sampler (tools may override them).
struct IntegratorDefaults {
    std::string type = "path";
    int maxDepth = -1;        // Mitsuba's meaning: 1 = emitters seen directly, -1 = unbounded
    int rrDepth = 5;          // depth from which Russian roulette starts (Mitsuba default)
    int sampleCount = 4;      // sampler sampleCount (Mitsuba's independent sampler default)
};

struct NamedBsdf {
    std::shared_ptr<const Bsdf> bsdf;
    std::string id;           // XML id or "" for anonymous nested BSDFs
    std::string origin;       // FILE:LINE
};

class Scene {
public:
    std::string filename;
    uint64_t contentHash = 0;           // FNV-1a over every file the scene read (XML, includes, meshes, images)

    std::vector<Shape> shapes;
    std::vector<NamedBsdf> bsdfs;
    std::vector<std::unique_ptr<Emitter>> emitters;
    PerspectiveCamera camera;
    IntegratorDefaults integrator;

    // What the loader did not use but accepted (rendering hints such as gamma or banner), reported once,
    // and its warnings (properties lt does not know, ignored; degenerate triangles removed), for the tool
    // to print.
    std::vector<std::string> ignoredHints;
    std::vector<std::string> warnings;

    // Bounds of the geometry (portals excluded) and the radius of its bounding sphere: environment and
    // directional emitters start their light paths on a disk of this radius.
    Bounds3 bounds;
    [[nodiscard]] double sceneRadius() const { return std::max(0.5 * bounds.diagonal(), 1e-3); }
    // The disk those paths start on (emitters/scene_disk.h), the one every infinite emitter was given.
    [[nodiscard]] SceneDisk sceneDisk() const { return {bounds.center(), sceneRadius()}; }

    // Choose an emitter in proportion to its power (luminance).
    DiscreteDistribution emitterSelection;
    // Indices of the environment emitters (constant, envmap), which escaped rays see.
    std::vector<int> environmentEmitters;

    [[nodiscard]] std::optional<SurfaceInteraction> intersect(const Ray& ray) const;
    // The surface interaction of a hit intersectHit found (shape index and distance included).
    [[nodiscard]] SurfaceInteraction interactionAt(const RayHit& hit) const;
    // The hit alone (shape, primitive, coordinates, distance), without the differential geometry.
    [[nodiscard]] std::optional<RayHit> intersectHit(const Ray& ray) const { return accel_.intersect(ray); }
    [[nodiscard]] bool occluded(const Ray& ray) const { return accel_.occluded(ray); }
    // The portals (shapes marked portal: kept out of the geometry above, seen only by the portal
    // perturbation): where `ray` first crosses one within its extent, over every portal shape.
    [[nodiscard]] bool hasPortals() const { return hasPortals_; }
    [[nodiscard]] std::optional<RayHit> intersectPortal(const Ray& ray) const {
        return hasPortals_ ? portals_.intersect(ray) : std::nullopt;
    }
    [[nodiscard]] size_t triangleCount() const;
    [[nodiscard]] const Bsdf* bsdfOf(const SurfaceInteraction& si) const;

    // Called by the loader once everything is in place.
    void finalize();
    // The shapes the geometry's accelerator holds: all but the portals (true where shapes[i] is geometry).
    [[nodiscard]] std::vector<bool> geometryShapes() const;

private:
    EmbreeAccel accel_;
    EmbreeAccel portals_;
    bool hasPortals_ = false;
};

// A property lt does not read (a typo, or a Mitsuba option lt has no counterpart for): a warning, as in
// Mitsuba, or an error (`--strict`).
enum class UnknownProperties { Warn, Fail };

// Load a Mitsuba XML scene (0.4-0.6, 2.x, 3.x; scene/xml_parser.cpp + scene/scene_builder.cpp). Throws
// lt::Error with a message naming the file, line and element.
std::unique_ptr<Scene> loadScene(const std::string& filename, const std::map<std::string, std::string>& parameters = {},
                                 UnknownProperties unknown = UnknownProperties::Warn);

} // namespace lt
