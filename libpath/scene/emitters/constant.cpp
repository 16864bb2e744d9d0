// Mitsuba's `constant` emitter: uniform radiance L arriving from every direction at infinity.
#include <limits>

#include "math/constants.h"
#include "math/warp.h"
#include "scene/emitter.h"
#include "scene/emitters/scene_disk.h"

namespace lt {

namespace {

class ConstantEmitter final : public Emitter {
public:
    explicit ConstantEmitter(const Spectrum& radiance) : radiance_(radiance) {}

    [[nodiscard]] uint8_t flags() const override { return EmitterInfinite; }
    [[nodiscard]] std::string typeName() const override { return "constant"; }
    void setSceneBounds(const Vec3& center, double radius) override { disk_ = {center, radius}; }

    // Uniform over the sphere of directions, as Mitsuba's constant emitter: sampleDirect does not know
    // the surface normal at ref (it may be a medium point or a pinhole), so cosine weighting is not
    // available here; MIS with BSDF sampling covers the cosine.
    [[nodiscard]] DirectSample sampleDirect(const Vec3& ref, const Vec2& u) const override {
        DirectSample ds;
        ds.wi = warp::squareToUniformSphere(u);
        ds.p = disk_.beyond(ref, ds.wi);
        ds.n = -ds.wi;
        ds.dist = std::numeric_limits<double>::infinity();
        ds.value = radiance_;
        ds.pdf = warp::squareToUniformSpherePdf();
        return ds;
    }

    [[nodiscard]] double pdfDirect(const Vec3&, const Vec3&, const Vec3&, const Vec3&) const override {
        return warp::squareToUniformSpherePdf();
    }

    // Direction uniform over the sphere, then a position on the scene disk perpendicular to it.
    [[nodiscard]] EmissionSample sampleEmission(const Vec2& uPos, const Vec2& uDir) const override {
        EmissionSample es;
        es.d = warp::squareToUniformSphere(uDir);
        es.p = disk_.sample(uPos, es.d);
        es.n = es.d;
        es.value = radiance_;
        es.pdfPos = disk_.pdf();
        es.pdfDir = warp::squareToUniformSpherePdf();
        return es;
    }

    void pdfEmission(const Vec3&, const Vec3&, const Vec3&, double& pdfPos, double& pdfDir) const override {
        pdfPos = disk_.pdf();
        pdfDir = warp::squareToUniformSpherePdf();
    }

    [[nodiscard]] Spectrum evalEnvironment(const Vec3& dir) const override {
        (void)dir;
        return radiance_;
    }

    // Power through the scene disk from all directions: L * 4 pi * pi r^2 (what sampleEmission
    // estimates; pbrt-v3 InfiniteAreaLight::Power up to its use of the mean radiance).
    [[nodiscard]] Spectrum power() const override { return radiance_ * (4 * Pi * disk_.area()); }

private:
    Spectrum radiance_;
    SceneDisk disk_;
};

} // namespace

std::unique_ptr<Emitter> makeConstantEmitter(const Spectrum& radiance) {
    return std::make_unique<ConstantEmitter>(radiance);
}

} // namespace lt
