// The BSDF interface (the contract; implementations live one per file beside it).
//
// Conventions, written down once:
// * Every direction is expressed in the local shading frame (math/frame.h: z = shading normal) and
//   points AWAY from the surface.
// * wi is the direction toward the vertex the path came from (the tracing direction reversed); wo is
//   the direction being sampled or evaluated. When tracing from the camera (Transport::Radiance), light
//   flows from wo to wi; when tracing from a light (Transport::Importance), importance flows from wo to
//   wi and light from wi to wo.
// * eval returns f_s without any cosine. Non-symmetric scattering (refraction) is made adjoint through
//   the Transport argument (Veach thesis section 5.2): in Radiance mode a refracted value carries the
//   (eta_wi / eta_wo)^2 factor, in Importance mode it does not. The shading-normal correction, which
//   needs the geometric normal, lives in bsdf/shading_correction.h.
// * pdf is a density in solid angle of wo given wi; the reverse density is pdf(wo, wi). Delta lobes have
//   pdf 0 and eval 0 here; they are reached only through sample() and deltaEval().
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "math/spectrum.h"
#include "math/vec.h"

namespace lt {

enum class Transport : uint8_t { Radiance, Importance };

// Lobe kinds as a bit set: what a BSDF can do, and what one sample did.
enum Lobe : uint8_t {
    LobeNone = 0,
    LobeDiffuse = 1 << 0,
    LobeGlossy = 1 << 1,
    LobeDelta = 1 << 2,
    LobeReflection = 1 << 3,
    LobeTransmission = 1 << 4,
};
using Lobes = uint8_t;

struct BsdfSample {
    Vec3 wo;                 // sampled direction, local frame, away from the surface
    Spectrum weight;         // f_s * |cos(wo)| / pdf, transport-mode aware (for delta: the lobe's weight)
    double pdf = 0;          // solid-angle density; for a delta lobe, the discrete probability of the lobe
    Lobes lobe = LobeNone;   // exactly one of Diffuse/Glossy/Delta, plus Reflection or Transmission
    double eta = 1;          // relative index crossed: eta_wo_side / eta_wi_side (1 for reflection)
};

// Indices of refraction on the two sides of a dielectric interface.
struct InterfaceEta {
    double interior = 1;     // below the shading normal (inside)
    double exterior = 1;     // above the shading normal (outside)
};

// How close wo must come to a delta lobe's exact direction for deltaEval to accept it. Directions
// recomputed from vertex positions miss it a little: rays leave surfaces from an offset origin
// (scene/ray.h) and hits carry float barycentrics, which on an edge of 1e-2 scene units turns the
// direction by up to ~1e-3. The lobes of one wi lie far apart (except within a fraction of a degree of
// grazing), so this does not confuse them.
inline constexpr double DeltaDirectionTolerance = 1e-3;

class Bsdf {
public:
    virtual ~Bsdf() = default;

    // f_s(wi, wo) for the non-delta lobes; uv selects texture values.
    [[nodiscard]] virtual Spectrum eval(const Vec3& wi, const Vec3& wo, const Vec2& uv, Transport mode) const = 0;
    // Solid-angle density with which sample() produces wo given wi (non-delta lobes only).
    [[nodiscard]] virtual double pdf(const Vec3& wi, const Vec3& wo, const Vec2& uv) const = 0;
    // Importance-sample wo. uLobe picks a lobe (Fresnel-weighted where there are several), u the
    // direction. Returns nothing when the sample is absorbed or invalid (zero weight).
    [[nodiscard]] virtual std::optional<BsdfSample> sample(const Vec3& wi, const Vec2& uv, Transport mode, double uLobe,
                                                           const Vec2& u) const = 0;

    // For delta lobes: the weight and discrete probability that sample() would return for a given
    // (wi, wo) pair when wo is the lobe's specular direction (reflected or refracted); nothing when wo
    // is not such a direction (within DeltaDirectionTolerance). The manifold walks use this after moving a
    // specular chain, and the tests check that it agrees with sample().
    [[nodiscard]] virtual std::optional<BsdfSample> deltaEval(const Vec3& wi, const Vec3& wo, const Vec2& uv,
                                                               Transport mode) const {
        (void)wi, (void)wo, (void)uv, (void)mode;
        return std::nullopt;
    }

    [[nodiscard]] virtual Lobes lobes() const = 0;
    // Beckmann-equivalent roughness alpha at uv: 0 for a purely delta BSDF, +infinity for a purely diffuse
    // one; for glossy lobes the Beckmann alpha with the same lobe width (GGX alpha / sqrt(2): the two
    // distributions agree to second order at the peak). Step sizes of HSLT and the specular/glossy
    // classification of manifold exploration read this.
    [[nodiscard]] virtual double roughness(const Vec2& uv) const = 0;
    // Dielectric interfaces report their indices; everything else does not refract.
    [[nodiscard]] virtual std::optional<InterfaceEta> eta() const { return std::nullopt; }
    // The Mitsuba plugin name ("roughconductor", ...), for reports.
    [[nodiscard]] virtual std::string typeName() const = 0;

    [[nodiscard]] bool hasDelta() const { return lobes() & LobeDelta; }
    [[nodiscard]] bool hasGlossy() const { return lobes() & LobeGlossy; }
    [[nodiscard]] bool hasDiffuse() const { return lobes() & LobeDiffuse; }
    [[nodiscard]] bool hasTransmission() const { return lobes() & LobeTransmission; }
};

} // namespace lt
