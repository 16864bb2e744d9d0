#include "scene/scene_features.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "bsdf/blend.h"
#include "bsdf/bump_mapped.h"
#include "bsdf/mask.h"
#include "bsdf/twosided.h"

namespace lt {

std::string describeBsdf(const Bsdf& bsdf) {
    if (const auto* t = dynamic_cast<const TwoSided*>(&bsdf)) return "twosided(" + describeBsdf(t->frontBsdf()) + ")";
    if (const auto* m = dynamic_cast<const MaskBsdf*>(&bsdf)) return "mask(" + describeBsdf(m->nested()) + ")";
    if (const auto* b = dynamic_cast<const BumpMappedBsdf*>(&bsdf)) return "bumpmap(" + describeBsdf(b->nested()) + ")";
    if (const auto* b = dynamic_cast<const BlendBsdf*>(&bsdf))
        return "blendbsdf(" + describeBsdf(b->first()) + ", " + describeBsdf(b->second()) + ")";
    return bsdf.typeName();
}

SceneFeatures analyzeScene(const Scene& scene) {
    SceneFeatures f;
    std::set<int> usedBsdfs;
    for (const auto& s : scene.shapes) {
        if (s.portal) {
            ++f.portals;
            continue;
        }
        ++f.shapes;
        ++f.shapeTypes[s.type];
        if (s.kind() == Shape::Kind::Triangles) f.triangles += s.mesh().triangles.size();
        if (s.kind() == Shape::Kind::Sphere) ++f.spheres;
        if (s.kind() == Shape::Kind::Disk) ++f.disks;
        if (s.bsdf >= 0) usedBsdfs.insert(s.bsdf);
    }
    f.minGlossyRoughness = INFINITY;
    std::vector<std::string> deltaNames, glossyNames;
    for (int b : usedBsdfs) {
        const auto& nb = scene.bsdfs[size_t(b)];
        const std::string desc = describeBsdf(*nb.bsdf);
        ++f.bsdfTypes[desc];
        const std::string name = nb.id.empty() ? desc : "'" + nb.id + "' (" + desc + ")";
        if (nb.bsdf->hasDelta()) {
            ++f.deltaBsdfs;
            deltaNames.push_back(name);
        }
        if (nb.bsdf->hasGlossy()) {
            ++f.glossyBsdfs;
            glossyNames.push_back(name);
            f.minGlossyRoughness = std::min(f.minGlossyRoughness, nb.bsdf->roughness({0.5, 0.5}));
        }
        if (nb.bsdf->hasDiffuse()) ++f.diffuseBsdfs;
        if (nb.bsdf->hasTransmission()) ++f.transmissiveBsdfs;
    }
    if (!std::isfinite(f.minGlossyRoughness)) f.minGlossyRoughness = 0;
    for (const auto& e : scene.emitters) ++f.emitterTypes[e->typeName()];

    auto list = [](const std::vector<std::string>& names) {
        std::string s;
        for (size_t i = 0; i < names.size() && i < 3; ++i) s += (i ? ", " : "") + names[i];
        if (names.size() > 3) s += " and " + std::to_string(names.size() - 3) + " more";
        return s;
    };
    f.specularChains = f.deltaBsdfs > 0;
    f.specularReason = f.specularChains ? "delta BSDFs: " + list(deltaNames)
                                        : "no delta (perfectly specular) BSDF: caustic and multi-chain "
                                          "perturbations of ideal specular chains cannot apply";
    f.glossySurfaces = f.glossyBsdfs > 0;
    f.glossyReason = f.glossySurfaces ? "glossy BSDFs: " + list(glossyNames)
                                      : "no glossy BSDF: half-vector and glossy manifold perturbations cannot apply";
    f.hasPortals = f.portals > 0;
    f.portalReason = f.hasPortals ? std::to_string(f.portals) + " portal shape(s)"
                                  : "no shape marked portal: the portal perturbation cannot apply";
    for (const auto& e : scene.emitters)
        if (e->isInfinite() && !(e->flags() & EmitterDeltaDirection)) f.environmentLight = true;
    f.environmentReason =
        f.environmentLight ? "an emitter at infinity (constant, envmap, sky, sun or sunsky)" : "no environment emitter";
    std::vector<std::string> deltaTypes, hittableTypes;
    for (const auto& e : scene.emitters) {
        auto& names = e->isDelta() ? deltaTypes : hittableTypes;
        if (std::find(names.begin(), names.end(), e->typeName()) == names.end()) names.push_back(e->typeName());
    }
    f.deltaLights = !deltaTypes.empty();
    f.deltaLightReason =
        f.deltaLights ? "delta emitters (" + list(deltaTypes) + "): paths cannot hit them"
        : hittableTypes.empty()
            ? "no emitters"
            : "no point, spot or directional emitter: paths can hit every emitter (" + list(hittableTypes) + ")";
    return f;
}

} // namespace lt
