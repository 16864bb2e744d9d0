// Emitters: the closed set Mitsuba 0.5/0.6 scenes use (area, point, spot, directional, constant, envmap; sky,
// sun and sunsky become an envmap and a directional emitter, scene/emitters/sun_sky.h).
//
// Conventions:
// * "direct" sampling picks a point on the emitter as seen from a reference point (next-event
//   estimation, BDPT's s = 1 strategy); its density is in SOLID ANGLE at the reference point.
// * "emission" sampling starts a light subpath: a position (density in AREA on the emitter; for
//   infinite emitters, area on a disk of the scene's bounding-sphere radius perpendicular to the
//   direction) and a direction (density in SOLID ANGLE).
// * Delta emitters (point, spot: delta position; directional: delta direction) report it in flags and
//   return densities of the non-delta part only; the delta part counts as 1.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "math/distribution.h"
#include "math/spectrum.h"
#include "math/transform.h"
#include "scene/shape.h"

namespace lt {

enum EmitterFlag : uint8_t {
    EmitterDeltaPosition = 1 << 0,
    EmitterDeltaDirection = 1 << 1,
    EmitterInfinite = 1 << 2,
    EmitterSurface = 1 << 3,
};

struct DirectSample {
    Vec3 p;                 // point on the emitter (infinite emitters: a point beyond the scene bounds)
    Vec3 n;                 // emitter normal at p (zero for point-like emitters; -wi for infinite ones)
    Vec3 wi;                // unit direction from the reference point toward p
    double dist = 0;        // distance to p (infinity for infinite emitters)
    Spectrum value;         // radiance arriving at the reference point along -wi (intensity / dist^2 for point lights)
    double pdf = 0;         // solid-angle density of wi at the reference point (1 for delta emitters)
    Vec2 coords;            // (prim, coords) of p on an area emitter's shape, for path records
    uint32_t prim = 0;
    double magnitude = 0;   // of p's primitive, for robust shadow rays (scene/ray.h)
};

struct EmissionSample {
    Vec3 p, n, d;           // start point, its normal (zero for point lights), direction leaving the emitter
    Spectrum value;         // emitted radiance along d at p (intensity for point-like emitters)
    double pdfPos = 0;      // area density of p
    double pdfDir = 0;      // solid-angle density of d given p
    Vec2 coords;
    uint32_t prim = 0;
};

class Emitter {
public:
    virtual ~Emitter() = default;

    [[nodiscard]] virtual uint8_t flags() const = 0;
    [[nodiscard]] virtual std::string typeName() const = 0;

    // Called once the scene's bounds are known (infinite and directional emitters need them).
    virtual void setSceneBounds(const Vec3& center, double radius) { (void)center, (void)radius; }

    [[nodiscard]] virtual DirectSample sampleDirect(const Vec3& ref, const Vec2& u) const = 0;
    // Solid-angle density that sampleDirect(ref) produces the point p (normal n) on the emitter; for an
    // infinite emitter p is ignored and -dir is the direction toward the emitter (pass dir = direction from ref).
    [[nodiscard]] virtual double pdfDirect(const Vec3& ref, const Vec3& p, const Vec3& n, const Vec3& dir) const = 0;

    [[nodiscard]] virtual EmissionSample sampleEmission(const Vec2& uPos, const Vec2& uDir) const = 0;
    virtual void pdfEmission(const Vec3& p, const Vec3& n, const Vec3& d, double& pdfPos, double& pdfDir) const = 0;

    // Radiant intensity of a delta-position emitter (point, spot) in the unit direction d; zero for the
    // others. A path starting at such an emitter carries it where a surface emitter carries radiance
    // (the position's delta stripped, as the area densities' "counts as 1").
    [[nodiscard]] virtual Spectrum intensity(const Vec3& d) const {
        (void)d;
        return {};
    }
    // Radiance leaving a point p (normal n) of a surface emitter in direction d (zero behind it).
    [[nodiscard]] virtual Spectrum evalSurface(const Vec3& p, const Vec3& n, const Vec3& d) const {
        (void)p, (void)n, (void)d;
        return {};
    }
    // Irradiance of a delta-direction emitter (directional) on a surface perpendicular to its direction;
    // zero for the others. A path starting at such an emitter carries it where an environment carries
    // radiance (the direction's delta stripped, as pdfDirect's "counts as 1").
    [[nodiscard]] virtual Spectrum irradiance() const { return {}; }
    // Radiance arriving from an infinite emitter along -dir (dir points from the scene toward the sky).
    [[nodiscard]] virtual Spectrum evalEnvironment(const Vec3& dir) const {
        (void)dir;
        return {};
    }
    // Total emitted power (approximate for textured emitters): light selection probabilities use it.
    [[nodiscard]] virtual Spectrum power() const = 0;

    [[nodiscard]] bool isDelta() const { return flags() & (EmitterDeltaPosition | EmitterDeltaDirection); }
    [[nodiscard]] bool isInfinite() const { return flags() & EmitterInfinite; }

    int shape = -1;            // for area emitters: the shape they sit on
    std::string origin;        // "FILE:LINE" for messages
};

// Factories, one per emitter type (implemented one per file in scene/emitters/).
std::unique_ptr<Emitter> makeAreaEmitter(const Shape& shape, int shapeIndex, const Spectrum& radiance);
std::unique_ptr<Emitter> makePointEmitter(const Vec3& position, const Spectrum& intensity);
// Mitsuba spot: local +z is the axis; cutoffAngle and beamWidth in degrees, smooth falloff between.
std::unique_ptr<Emitter> makeSpotEmitter(const Transform& toWorld, const Spectrum& intensity, double cutoffAngleDeg,
                                         double beamWidthDeg);
// direction: the direction light travels; irradiance on a surface perpendicular to it.
std::unique_ptr<Emitter> makeDirectionalEmitter(const Vec3& direction, const Spectrum& irradiance);
std::unique_ptr<Emitter> makeConstantEmitter(const Spectrum& radiance);
// Lat-long environment map read with OpenImageIO (Mitsuba's envmap orientation: +y up, toWorld
// applied), importance sampled by luminance x sin(theta). Throws lt::Error naming the file.
std::unique_ptr<Emitter> makeEnvmapEmitter(const std::string& filename, const Transform& toWorld, double scale);
// A lat-long image in memory, row-major, Mitsuba's envmap layout (scene/emitters/lat_long.h).
struct LatLongImage {
    int width = 0, height = 0;
    std::vector<Spectrum> pixels;
};
// The same emitter on an image made in memory (the sky and sun models bake theirs); `type` is the
// plugin name it reports (typeName()).
std::unique_ptr<Emitter> makeEnvmapEmitter(LatLongImage image, const Transform& toWorld, const std::string& type);

} // namespace lt
