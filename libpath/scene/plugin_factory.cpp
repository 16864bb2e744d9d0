#include "scene/plugin_factory.h"

#include "bsdf/blend.h"
#include "bsdf/bump_mapped.h"
#include "bsdf/conductor.h"
#include "bsdf/conductor_presets.h"
#include "bsdf/dielectric.h"
#include "bsdf/diffuse.h"
#include "bsdf/ior_presets.h"
#include "bsdf/mask.h"
#include "bsdf/phong.h"
#include "bsdf/plastic.h"
#include "bsdf/roughconductor.h"
#include "bsdf/roughdielectric.h"
#include "bsdf/roughplastic.h"
#include "bsdf/thindielectric.h"
#include "bsdf/twosided.h"
#include "bsdf/ward.h"
#include "util/error.h"

namespace lt {

namespace {

std::string joined(const std::vector<std::string>& names) {
    std::string s;
    for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
    return s;
}

MicrofacetType distribution(const SceneObject& o) {
    const std::string d = o.getString("distribution", "beckmann");
    if (d == "beckmann") return MicrofacetType::Beckmann;
    if (d == "ggx") return MicrofacetType::GGX;
    if (d == "phong" || d == "as") o.fail("microfacet distribution '" + d + "' is not supported (use beckmann or ggx)");
    o.fail("unknown microfacet distribution '" + d + "' (use beckmann or ggx)");
}

// Mitsuba: `alpha` sets both, or `alphaU` and `alphaV` (anisotropic). Default 0.1.
void roughness(const SceneObject& o, double& alphaU, double& alphaV) {
    if (o.has("alpha") && (o.has("alphaU") || o.has("alphaV"))) o.fail("give either alpha or alphaU/alphaV, not both");
    if (o.has("alphaU") != o.has("alphaV")) o.fail("alphaU and alphaV must be given together");
    if (o.has("alphaU")) {
        alphaU = o.getFloat("alphaU");
        alphaV = o.getFloat("alphaV");
    } else {
        alphaU = alphaV = o.getFloat("alpha", 0.1);
    }
    if (!(alphaU > 0) || !(alphaV > 0)) o.fail("roughness alpha must be positive (use the smooth variant for alpha = 0)");
}

// eta/k of a conductor: a named `material`, or explicit eta and k (Mitsuba default "Cu").
void conductorIor(const SceneObject& o, Spectrum& eta, Spectrum& k) {
    if (o.has("material") && (o.has("eta") || o.has("k"))) o.fail("give either material or eta/k, not both");
    if (o.has("eta") || o.has("k")) {
        if (!o.has("eta") || !o.has("k")) o.fail("eta and k must be given together");
        eta = o.getSpectrum("eta");
        k = o.getSpectrum("k");
        return;
    }
    const std::string name = o.getString("material", "Cu");
    const auto preset = lookupConductor(name);
    if (!preset) o.fail("unknown conductor material '" + name + "' (known: " + joined(conductorPresetNames()) + ")");
    eta = preset->eta;
    k = preset->k;
}

// A bitmap's wrap mode by Mitsuba's name.
BitmapLookup::Wrap wrapMode(const SceneObject& o, const std::string& name) {
    using Wrap = BitmapLookup::Wrap;
    if (name == "repeat") return Wrap::Repeat;
    if (name == "mirror") return Wrap::Mirror;
    if (name == "clamp") return Wrap::Clamp;
    if (name == "zero") return Wrap::Zero;
    if (name == "one") return Wrap::One;
    o.fail("wrap mode '" + name + "' is not one of repeat, mirror, clamp, zero, one");
}

} // namespace

double PluginFactory::ior(const SceneObject& o, const std::string& key, double def) {
    auto it = o.props.find(key);
    if (it == o.props.end()) return def;
    if (it->second.type == Property::Type::String) {
        const std::string name = o.getString(key);
        const auto v = lookupIor(name);
        if (!v) o.fail("unknown index of refraction '" + name + "' for " + key + " (known: " + joined(iorPresetNames()) + ")");
        return *v;
    }
    return o.getFloat(key);
}

GlossyDiffuseParams PluginFactory::glossyDiffuse(const SceneObject& o) {
    GlossyDiffuseParams p;
    p.specularReflectance = textureParam(o, "specularReflectance", Spectrum(0.2));
    p.diffuseReflectance = textureParam(o, "diffuseReflectance", Spectrum(0.5));
    p.ensureEnergyConservation = o.getBoolean("ensureEnergyConservation", true);
    return p;
}

void PluginFactory::noteEnergyScale(const SceneObject& o, const GlossyDiffuseBsdf& b) {
    if (b.energyScale() < 1)
        warnings.push_back(o.where() + ": specularReflectance + diffuseReflectance exceed 1; both scaled by " +
                           std::to_string(b.energyScale()) +
                           " to conserve energy, as Mitsuba does (ensureEnergyConservation = false keeps them)");
}

std::shared_ptr<const Bsdf> PluginFactory::nestedBsdf(const SceneObject& parent, const SceneObject& child) {
    if (child.type == "bumpmap")
        child.fail("a bumpmap must be the outermost BSDF of its shapes (lt tilts the surface's shading frame)");
    consumed_.insert({&parent, &child});
    return bsdf(child);
}

void PluginFactory::finish(const SceneObject& o, const std::set<std::string>& hints) {
    unread_.check(o, hints);
    for (const auto& c : o.children) {
        // Every nested object must have been consumed as a texture or nested BSDF.
        if ((c->tag == "texture" || c->tag == "bsdf") && consumed_.count({&o, c.get()})) continue;
        c->fail("not used by its <" + o.tag + " type=\"" + o.type + "\"> (check its name)");
    }
}

std::shared_ptr<const Texture> PluginFactory::texture(const SceneObject& o) {
    if (auto it = textures_.find(o.declaration()); it != textures_.end()) return it->second;
    const Vec2 offset{o.getFloat("uoffset", 0.0), o.getFloat("voffset", 0.0)};
    const Vec2 scale{o.getFloat("uscale", 1.0), o.getFloat("vscale", 1.0)};
    std::shared_ptr<const Texture> t;
    if (o.type == "bitmap") {
        BitmapLookup lookup;
        const std::string filter = o.getString("filterType", "ewa");
        if (filter == "nearest")
            lookup.filter = BitmapLookup::Filter::Nearest;
        else if (filter != "ewa" && filter != "trilinear" && filter != "bilinear")
            o.fail("filterType '" + filter + "' is not one of ewa, trilinear, bilinear, nearest");
        const std::string wrap = o.getString("wrapMode", "repeat");
        lookup.wrapU = wrapMode(o, o.getString("wrapModeU", wrap));
        lookup.wrapV = wrapMode(o, o.getString("wrapModeV", wrap));
        const std::string file = resolve_(o, o.getString("filename"));
        try {
            t = std::make_shared<BitmapTexture>(file, o.getFloat("gamma", 0.0), offset, scale,
                                                o.getString("channel", ""), lookup);
        } catch (const Error& e) {
            o.fail(e.what());
        }
        finish(o, {"maxAnisotropy", "cache"});
    } else if (o.type == "scale") {
        const auto nested = o.childrenWithTag("texture");
        if (nested.size() != 1) o.fail("scale takes one nested texture");
        consumed_.insert({&o, nested[0].get()});
        t = std::make_shared<ScaledTexture>(texture(*nested[0]), o.getSpectrum("scale", Spectrum(1.0)));
        finish(o);
    } else if (o.type == "checkerboard") {
        t = std::make_shared<CheckerboardTexture>(o.getSpectrum("color0", Spectrum(0.4)),
                                                  o.getSpectrum("color1", Spectrum(0.2)), offset, scale);
        finish(o);
    } else {
        o.fail("unknown texture type (lt reads bitmap, checkerboard and scale)");
    }
    textures_[o.declaration()] = t;
    return t;
}

std::shared_ptr<const Texture> PluginFactory::textureParam(const SceneObject& o, const std::string& key,
                                                           const Spectrum& def) {
    if (auto child = o.namedChild(key)) {
        if (child->tag != "texture") child->fail("'" + key + "' must be a texture");
        if (o.has(key)) o.fail("'" + key + "' is given both as a value and as a texture");
        consumed_.insert({&o, child.get()});
        return texture(*child);
    }
    return std::make_shared<ConstantTexture>(o.getSpectrum(key, def));
}

std::shared_ptr<const Bsdf> PluginFactory::defaultBsdf() {
    return std::make_shared<Diffuse>(DiffuseParams{std::make_shared<ConstantTexture>(Spectrum(0.5))});
}

std::shared_ptr<const Bsdf> PluginFactory::bsdf(const SceneObject& o) {
    if (auto it = bsdfs_.find(o.declaration()); it != bsdfs_.end()) return it->second;
    std::shared_ptr<const Bsdf> b;
    try {
        b = interfaceBsdf(o);
        if (!b) b = layeredBsdf(o);
        if (!b) b = diffuseBsdf(o);
        if (!b)
            o.fail("unknown BSDF type (lt reads diffuse, twosided, dielectric, thindielectric, roughdielectric, "
                   "conductor, roughconductor, plastic, roughplastic, phong, ward, blendbsdf, mask, bumpmap)");
    } catch (const Error& e) {
        const std::string what = e.what();
        if (what.find(o.file + ':') == 0) throw;
        o.fail(what);
    }
    bsdfs_[o.declaration()] = b;
    return b;
}

void PluginFactory::dielectricParams(const SceneObject& o, DielectricParams& p) {
    p.intIOR = ior(o, "intIOR", p.intIOR);
    p.extIOR = ior(o, "extIOR", p.extIOR);
    p.specularReflectance = textureParam(o, "specularReflectance", Spectrum(1.0));
    p.specularTransmittance = textureParam(o, "specularTransmittance", Spectrum(1.0));
}

std::shared_ptr<const Bsdf> PluginFactory::interfaceBsdf(const SceneObject& o) {
    std::shared_ptr<const Bsdf> b;
    if (o.type == "dielectric" || o.type == "thindielectric") {
        DielectricParams p;
        dielectricParams(o, p);
        if (o.type == "dielectric")
            b = std::make_shared<Dielectric>(p);
        else
            b = std::make_shared<ThinDielectric>(p);
        finish(o);
    } else if (o.type == "roughdielectric") {
        RoughDielectricParams p;
        p.distribution = distribution(o);
        roughness(o, p.alphaU, p.alphaV);
        dielectricParams(o, p);
        b = std::make_shared<RoughDielectric>(p);
        finish(o, {"sampleVisible"});
    } else if (o.type == "conductor" || o.type == "roughconductor") {
        RoughConductorParams p;
        const bool rough = o.type == "roughconductor";
        if (rough) {
            p.distribution = distribution(o);
            roughness(o, p.alphaU, p.alphaV);
        }
        conductorIor(o, p.eta, p.k);
        p.extEta = ior(o, "extEta", p.extEta);
        p.specularReflectance = textureParam(o, "specularReflectance", Spectrum(1.0));
        if (rough)
            b = std::make_shared<RoughConductor>(p);
        else
            b = std::make_shared<Conductor>(static_cast<const ConductorParams&>(p));
        finish(o, rough ? std::set<std::string>{"sampleVisible"} : std::set<std::string>{});
    } else if (o.type == "plastic" || o.type == "roughplastic") {
        b = plasticBsdf(o);
    }
    return b;
}

std::shared_ptr<const Bsdf> PluginFactory::plasticBsdf(const SceneObject& o) {
    const bool rough = o.type == "roughplastic";
    RoughPlasticParams p;
    if (rough) {
        p.distribution = distribution(o);
        double au = 0.1, av = 0.1;
        roughness(o, au, av);
        if (au != av) o.fail("roughplastic is isotropic: give alpha, not alphaU/alphaV");
        p.alpha = au;
    }
    p.intIOR = ior(o, "intIOR", p.intIOR);
    p.extIOR = ior(o, "extIOR", p.extIOR);
    p.diffuseReflectance = textureParam(o, "diffuseReflectance", Spectrum(0.5));
    p.specularReflectance = textureParam(o, "specularReflectance", Spectrum(1.0));
    p.nonlinear = o.getBoolean("nonlinear", false);
    std::shared_ptr<const Bsdf> b;
    if (rough)
        b = std::make_shared<RoughPlastic>(p);
    else
        b = std::make_shared<Plastic>(static_cast<const PlasticParams&>(p));
    finish(o, rough ? std::set<std::string>{"sampleVisible"} : std::set<std::string>{});
    return b;
}

std::shared_ptr<const Bsdf> PluginFactory::layeredBsdf(const SceneObject& o) {
    std::shared_ptr<const Bsdf> b;
    const auto nested = o.childrenWithTag("bsdf");
    if (o.type == "twosided") {
        if (nested.empty() || nested.size() > 2) o.fail("twosided takes one or two nested BSDFs");
        TwoSidedParams p;
        p.front = nestedBsdf(o, *nested[0]);
        if (nested.size() == 2) p.back = nestedBsdf(o, *nested[1]);
        b = std::make_shared<TwoSided>(p);
    } else if (o.type == "blendbsdf") {
        if (nested.size() != 2) o.fail("blendbsdf takes two nested BSDFs");
        BlendParams p;
        p.weight = textureParam(o, "weight", Spectrum(0.5));
        p.first = nestedBsdf(o, *nested[0]);
        p.second = nestedBsdf(o, *nested[1]);
        b = std::make_shared<BlendBsdf>(p);
    } else if (o.type == "bumpmap") {
        const auto textures = o.childrenWithTag("texture");
        if (nested.size() != 1 || textures.size() != 1)
            o.fail("bumpmap takes one displacement texture and one nested BSDF");
        consumed_.insert({&o, textures[0].get()});
        std::shared_ptr<const Texture> displacement = texture(*textures[0]);
        // Mitsuba 3's bumpmap scales the displacement (`scale`, default 1); 0.6's has no such option.
        if (o.has("scale")) displacement = std::make_shared<ScaledTexture>(displacement, Spectrum(o.getFloat("scale")));
        b = std::make_shared<BumpMappedBsdf>(displacement, nestedBsdf(o, *nested[0]));
    } else if (o.type == "mask") {
        if (nested.size() != 1) o.fail("mask takes one nested BSDF");
        MaskParams p;
        p.opacity = textureParam(o, "opacity", Spectrum(0.5));
        p.nested = nestedBsdf(o, *nested[0]);
        b = std::make_shared<MaskBsdf>(p);
    }
    if (b) finish(o);
    return b;
}

std::shared_ptr<const Bsdf> PluginFactory::diffuseBsdf(const SceneObject& o) {
    std::shared_ptr<const Bsdf> b;
    if (o.type == "diffuse") {
        // Mitsuba 0.6 also takes the reflectance as diffuseReflectance.
        const bool alias = o.has("diffuseReflectance") || o.namedChild("diffuseReflectance");
        b = std::make_shared<Diffuse>(
            DiffuseParams{textureParam(o, alias ? "diffuseReflectance" : "reflectance", Spectrum(0.5))});
    } else if (o.type == "phong") {
        PhongParams p;
        p.exponent = textureParam(o, "exponent", Spectrum(30.0));
        p.reflectances = glossyDiffuse(o);
        const auto phong = std::make_shared<Phong>(p);
        noteEnergyScale(o, *phong);
        b = phong;
    } else if (o.type == "ward") {
        WardParams p;
        const std::string variant = o.getString("variant", "balanced");
        if (variant == "ward")
            p.variant = WardVariant::Ward;
        else if (variant == "ward-duer")
            p.variant = WardVariant::WardDuer;
        else if (variant == "balanced")
            p.variant = WardVariant::Balanced;
        else
            o.fail("variant must be ward, ward-duer or balanced, not '" + variant + "'");
        // Mitsuba's ward: alphaU and alphaV each default to alpha (0.1); any of the three may be a texture.
        const auto alpha = textureParam(o, "alpha", Spectrum(0.1));
        const auto given = [&](const char* key) { return o.has(key) || o.namedChild(key) != nullptr; };
        p.alphaU = given("alphaU") ? textureParam(o, "alphaU", Spectrum(0.1)) : alpha;
        p.alphaV = given("alphaV") ? textureParam(o, "alphaV", Spectrum(0.1)) : alpha;
        p.reflectances = glossyDiffuse(o);
        const auto ward = std::make_shared<Ward>(p);
        noteEnergyScale(o, *ward);
        b = ward;
    }
    if (b) finish(o);
    return b;
}

} // namespace lt
