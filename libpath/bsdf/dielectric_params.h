// What Mitsuba's dielectric interfaces take (`dielectric`, `thindielectric`, `roughdielectric`): the two indices
// and the reflectance and transmittance multipliers, read and checked in one place for the three.
#pragma once

#include <memory>
#include <string>

#include "bsdf/ior_presets.h"
#include "texture/texture.h"
#include "util/error.h"

namespace lt {

// Indices are numbers here; names ("bk7", "air", ...) are resolved with lookupIor (bsdf/ior_presets.h).
struct DielectricParams {
    double intIOR = 1.5046;   // Mitsuba default "bk7"
    double extIOR = 1.000277; // Mitsuba default "air"
    std::shared_ptr<const Texture> specularReflectance = std::make_shared<ConstantTexture>(Spectrum(1.0));
    std::shared_ptr<const Texture> specularTransmittance = std::make_shared<ConstantTexture>(Spectrum(1.0));

    // intIOR / extIOR; throws lt::Error naming `plugin` for a non-positive or non-finite index or a null texture.
    [[nodiscard]] double relativeEta(const std::string& plugin) const {
        checkIorPair(plugin, intIOR, extIOR);
        if (!specularReflectance || !specularTransmittance) throw Error(plugin + ": null texture");
        return intIOR / extIOR;
    }
};

} // namespace lt
