// What a scene contains and therefore which strategies and stages can help on it. lt-inspect reports
// it; later, `lt-mutate --strategies auto` and the gradient tools read the same answers to leave out
// what cannot help (the third promise: skip what a scene does not need, and say why).
#pragma once

#include <map>
#include <string>

#include "scene/scene.h"

namespace lt {

struct SceneFeatures {
    size_t shapes = 0, triangles = 0, spheres = 0, disks = 0, portals = 0;
    std::map<std::string, size_t> shapeTypes;      // Mitsuba plugin name -> count
    std::map<std::string, size_t> bsdfTypes;       // e.g. "twosided(diffuse)" -> count (of shapes' BSDFs)
    std::map<std::string, size_t> emitterTypes;
    size_t deltaBsdfs = 0, glossyBsdfs = 0, diffuseBsdfs = 0, transmissiveBsdfs = 0;
    double minGlossyRoughness = 0;                 // smallest Beckmann-equivalent alpha among glossy BSDFs

    // Each answer comes with the reason, in words, for the report.
    bool specularChains = false;   std::string specularReason;
    bool glossySurfaces = false;   std::string glossyReason;
    bool hasPortals = false;       std::string portalReason;
    bool environmentLight = false; std::string environmentReason;
    bool deltaLights = false;      std::string deltaLightReason;
};

[[nodiscard]] SceneFeatures analyzeScene(const Scene& scene);

// "twosided(diffuse)" or "blendbsdf(diffuse, roughconductor)" style description of a BSDF, following
// nested BSDFs.
[[nodiscard]] std::string describeBsdf(const Bsdf& bsdf);

} // namespace lt
