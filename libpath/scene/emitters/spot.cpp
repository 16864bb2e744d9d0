// Mitsuba 0.5's `spot` emitter: a point source at toWorld's origin shining along toWorld's +z, with
// intensity I inside beamWidth, a falloff linear in the angle between beamWidth and cutoffAngle, and
// nothing beyond cutoffAngle (Mitsuba spot.cpp, falloffCurve; its projection texture is not supported).
#include <cmath>

#include "math/constants.h"
#include "util/error.h"
#include "math/frame.h"
#include "math/warp.h"
#include "scene/emitter.h"
#include "scene/emitters/point_source.h"

namespace lt {

namespace {

class SpotEmitter final : public Emitter {
public:
    // Only the origin and the direction of +z are taken from toWorld (Mitsuba assumes a rigid
    // transform; a scale would otherwise distort the cone).
    SpotEmitter(const Transform& toWorld, const Spectrum& intensity, double cutoffRad, double beamRad)
        : position_(toWorld.point({0, 0, 0})), frame_(Frame::fromNormal(normalize(toWorld.vector({0, 0, 1})))),
          intensity_(intensity), cutoff_(cutoffRad), beam_(beamRad), cosCutoff_(std::cos(cutoffRad)),
          cosBeam_(std::cos(beamRad)) {}

    [[nodiscard]] uint8_t flags() const override { return EmitterDeltaPosition; }
    [[nodiscard]] std::string typeName() const override { return "spot"; }

    [[nodiscard]] DirectSample sampleDirect(const Vec3& ref, const Vec2& u) const override {
        (void)u;
        DirectSample ds = pointSourceSample(position_, ref);
        if (ds.pdf > 0) ds.value = intensity_ * (falloff(-ds.wi) / (ds.dist * ds.dist));
        return ds;
    }

    [[nodiscard]] Spectrum intensity(const Vec3& d) const override { return intensity_ * falloff(d); }

    // Delta position: the discrete choice counts as 1 (emitter.h).
    [[nodiscard]] double pdfDirect(const Vec3&, const Vec3&, const Vec3&, const Vec3&) const override { return 1; }

    // Directions uniform in the cutoff cone, as Mitsuba's spot sampleRay.
    [[nodiscard]] EmissionSample sampleEmission(const Vec2& uPos, const Vec2& uDir) const override {
        (void)uPos;
        EmissionSample es;
        es.p = position_;
        es.d = frame_.toWorld(warp::squareToUniformCone(uDir, cosCutoff_));
        es.value = intensity_ * falloff(es.d);
        es.pdfPos = 1;
        es.pdfDir = warp::squareToUniformConePdf(cosCutoff_);
        return es;
    }

    void pdfEmission(const Vec3&, const Vec3&, const Vec3& d, double& pdfPos, double& pdfDir) const override {
        pdfPos = 1;
        pdfDir = dot(frame_.n, d) > cosCutoff_ ? warp::squareToUniformConePdf(cosCutoff_) : 0.0;
    }

    // I times the solid-angle integral of the falloff: 2 pi [(1 - cos b) + int_b^c (c - t)/(c - b) sin t dt]
    // = 2 pi [1 - (sin c - sin b) / (c - b)], which tends to 2 pi (1 - cos c) as b -> c.
    [[nodiscard]] Spectrum power() const override {
        const double width = cutoff_ - beam_;
        const double mean = width > 1e-6 ? (std::sin(cutoff_) - std::sin(beam_)) / width : std::cos(cutoff_);
        return intensity_ * (TwoPi * (1 - mean));
    }

private:
    // Mitsuba's falloffCurve: 1 inside the beam, linear in the angle down to 0 at the cutoff.
    [[nodiscard]] double falloff(const Vec3& dWorld) const {
        const double cosTheta = dot(frame_.n, dWorld);
        if (cosTheta <= cosCutoff_) return 0;
        if (cosTheta >= cosBeam_) return 1;
        return (cutoff_ - safeAcos(cosTheta)) / (cutoff_ - beam_);
    }

    Vec3 position_;
    Frame frame_;
    Spectrum intensity_;
    double cutoff_, beam_, cosCutoff_, cosBeam_;
};

} // namespace

std::unique_ptr<Emitter> makeSpotEmitter(const Transform& toWorld, const Spectrum& intensity, double cutoffAngleDeg,
                                         double beamWidthDeg) {
    // Mitsuba asserts cutoffAngle >= beamWidth; the cone warp needs 0 < cutoff <= 180 degrees.
    if (!(cutoffAngleDeg > 0 && cutoffAngleDeg <= 180))
        throw Error("spot emitter: cutoffAngle must be in (0, 180] degrees");
    if (!(beamWidthDeg >= 0 && beamWidthDeg <= cutoffAngleDeg))
        throw Error("spot emitter: beamWidth must be in [0, cutoffAngle]");
    return std::make_unique<SpotEmitter>(toWorld, intensity, degToRad(cutoffAngleDeg), degToRad(beamWidthDeg));
}

} // namespace lt
