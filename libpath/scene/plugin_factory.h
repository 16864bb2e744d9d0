// Builders of BSDFs and textures from their XML descriptions, shared by the scene builder. Each reads
// the Mitsuba parameters of its plugin (with Mitsuba's defaults) and marks them used, so what is left
// unread is reported by UnreadProperties.
#pragma once

#include <functional>
#include <memory>
#include <set>
#include <string>
#include <utility>

#include "bsdf/bsdf.h"
#include "bsdf/dielectric_params.h"
#include "bsdf/glossy_diffuse.h"
#include "scene/scene_object.h"
#include "texture/texture.h"

namespace lt {

// Resolves a file name of the scene (relative to the scene's directory) and records it for the
// scene's content hash.
using FileResolver = std::function<std::string(const SceneObject& owner, const std::string& filename)>;

class PluginFactory {
public:
    PluginFactory(FileResolver resolve, UnreadProperties& unread) : resolve_(std::move(resolve)), unread_(unread) {}

    // A texture-valued parameter: a nested/referenced <texture name="key">, an rgb/spectrum/float
    // property, or the default.
    [[nodiscard]] std::shared_ptr<const Texture> textureParam(const SceneObject& o, const std::string& key,
                                                              const Spectrum& def);
    [[nodiscard]] std::shared_ptr<const Texture> texture(const SceneObject& o);
    [[nodiscard]] std::shared_ptr<const Bsdf> bsdf(const SceneObject& o);
    // Mitsuba gives shapes without a BSDF a diffuse one with reflectance 0.5.
    [[nodiscard]] static std::shared_ptr<const Bsdf> defaultBsdf();

    // What the plugins changed on their own, for the scene's warnings (e.g. reflectances scaled down
    // to conserve energy, as Mitsuba does).
    std::vector<std::string> warnings;

private:
    // The BSDFs of one family each (nothing for another type): the interfaces (dielectric, thindielectric,
    // roughdielectric, conductor, roughconductor, plastic, roughplastic), those made of nested BSDFs (twosided,
    // blendbsdf, bumpmap, mask), and the diffuse and glossy-diffuse ones (diffuse, phong, ward).
    [[nodiscard]] std::shared_ptr<const Bsdf> interfaceBsdf(const SceneObject& o);
    [[nodiscard]] std::shared_ptr<const Bsdf> plasticBsdf(const SceneObject& o);
    [[nodiscard]] std::shared_ptr<const Bsdf> layeredBsdf(const SceneObject& o);
    [[nodiscard]] std::shared_ptr<const Bsdf> diffuseBsdf(const SceneObject& o);
    // The parameters every dielectric interface takes.
    void dielectricParams(const SceneObject& o, DielectricParams& p);
    // An index of refraction given as a number or a name ("bk7", "air", ...).
    [[nodiscard]] double ior(const SceneObject& o, const std::string& key, double def);
    // A BSDF nested in (or referenced by) `parent`, recorded as consumed by it.
    [[nodiscard]] std::shared_ptr<const Bsdf> nestedBsdf(const SceneObject& parent, const SceneObject& child);
    // The reflectances of phong and ward, with their energy-conservation switch.
    [[nodiscard]] GlossyDiffuseParams glossyDiffuse(const SceneObject& o);
    // A warning when Mitsuba's energy conservation scaled a glossy BSDF's reflectances.
    void noteEnergyScale(const SceneObject& o, const GlossyDiffuseBsdf& b);
    void finish(const SceneObject& o, const std::set<std::string>& hints = {});

    FileResolver resolve_;
    UnreadProperties& unread_;
    // Built objects by declaration (SceneObject::declaration()).
    std::map<const SceneObject*, std::shared_ptr<const Texture>> textures_;
    std::map<const SceneObject*, std::shared_ptr<const Bsdf>> bsdfs_;
    // (parent, nested or referenced child) for every child a plugin consumed: a child missing here was not
    // read by that parent (a misnamed <ref name=...>, say), which is an error, whoever else reads it.
    std::set<std::pair<const SceneObject*, const SceneObject*>> consumed_;
};

} // namespace lt
