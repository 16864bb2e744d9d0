// Builders of BSDFs and textures from their XML descriptions, shared by the scene builder. Each reads
// the Mitsuba parameters of its plugin (with Mitsuba's defaults) and marks them used, so unknown
// parameters are reported by SceneObject::checkUnused.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "bsdf/bsdf.h"
#include "scene/scene_object.h"
#include "texture/texture.h"

namespace lt {

// Resolves a file name of the scene (relative to the scene's directory) and records it for the
// scene's content hash.
using FileResolver = std::function<std::string(const SceneObject& owner, const std::string& filename)>;

class PluginFactory {
public:
    explicit PluginFactory(FileResolver resolve) : resolve_(std::move(resolve)) {}

    // A texture-valued parameter: a nested/referenced <texture name="key">, an rgb/spectrum/float
    // property, or the default.
    [[nodiscard]] std::shared_ptr<const Texture> textureParam(const SceneObject& o, const std::string& key,
                                                              const Spectrum& def);
    [[nodiscard]] std::shared_ptr<const Texture> texture(const SceneObject& o);
    [[nodiscard]] std::shared_ptr<const Bsdf> bsdf(const SceneObject& o);
    // Mitsuba gives shapes without a BSDF a diffuse one with reflectance 0.5.
    [[nodiscard]] static std::shared_ptr<const Bsdf> defaultBsdf();

    // Rendering hints reported as ignored, in "plugin.property" form.
    std::vector<std::string> ignored;

private:
    // An index of refraction given as a number or a name ("bk7", "air", ...).
    [[nodiscard]] double ior(const SceneObject& o, const std::string& key, double def);
    void finish(const SceneObject& o, const std::set<std::string>& hints = {});

    FileResolver resolve_;
    std::map<const SceneObject*, std::shared_ptr<const Texture>> textures_;
    std::map<const SceneObject*, std::shared_ptr<const Bsdf>> bsdfs_;
};

} // namespace lt
