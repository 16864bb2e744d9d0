// Mitsuba's `point` emitter: an isotropic point source of radiant intensity I (W/sr) at a position.
#include "math/constants.h"
#include "util/error.h"
#include "math/warp.h"
#include "scene/emitter.h"
#include "scene/emitters/point_source.h"

namespace lt {

namespace {

class PointEmitter final : public Emitter {
public:
    PointEmitter(const Vec3& position, const Spectrum& intensity) : position_(position), intensity_(intensity) {}

    [[nodiscard]] uint8_t flags() const override { return EmitterDeltaPosition; }
    [[nodiscard]] std::string typeName() const override { return "point"; }

    // The only point there is; arriving radiance carries the inverse-square law (pbrt-v3 PointLight).
    [[nodiscard]] DirectSample sampleDirect(const Vec3& ref, const Vec2& u) const override {
        (void)u;
        DirectSample ds = pointSourceSample(position_, ref);
        if (ds.pdf > 0) ds.value = intensity_ / (ds.dist * ds.dist);
        return ds;
    }

    // Delta position: the discrete choice counts as 1 (emitter.h).
    [[nodiscard]] double pdfDirect(const Vec3&, const Vec3&, const Vec3&, const Vec3&) const override { return 1; }

    // Delta position, uniform direction over the sphere.
    [[nodiscard]] EmissionSample sampleEmission(const Vec2& uPos, const Vec2& uDir) const override {
        (void)uPos;
        EmissionSample es;
        es.p = position_;
        es.d = warp::squareToUniformSphere(uDir);
        es.value = intensity_;
        es.pdfPos = 1;
        es.pdfDir = warp::squareToUniformSpherePdf();
        return es;
    }

    void pdfEmission(const Vec3&, const Vec3&, const Vec3&, double& pdfPos, double& pdfDir) const override {
        pdfPos = 1;
        pdfDir = warp::squareToUniformSpherePdf();
    }

    [[nodiscard]] Spectrum intensity(const Vec3&) const override { return intensity_; }
    [[nodiscard]] Spectrum power() const override { return intensity_ * (4 * Pi); }

private:
    Vec3 position_;
    Spectrum intensity_;
};

} // namespace

std::unique_ptr<Emitter> makePointEmitter(const Vec3& position, const Spectrum& intensity) {
    if (!isFinite(position)) throw Error("point emitter: position is not finite");
    return std::make_unique<PointEmitter>(position, intensity);
}

} // namespace lt
