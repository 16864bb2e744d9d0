// Mitsuba's `directional` emitter: light arriving from one direction, with irradiance E on a surface
// perpendicular to it (a delta in direction: radiance E delta(w - w0)).
#include <limits>

#include "util/error.h"
#include "scene/emitter.h"
#include "scene/emitters/scene_disk.h"

namespace lt {

namespace {

class DirectionalEmitter final : public Emitter {
public:
    DirectionalEmitter(const Vec3& direction, const Spectrum& irradiance)
        : d_(normalize(direction)), irradiance_(irradiance) {}

    [[nodiscard]] uint8_t flags() const override { return EmitterDeltaDirection | EmitterInfinite; }
    [[nodiscard]] std::string typeName() const override { return "directional"; }
    void setSceneBounds(const Vec3& center, double radius) override { disk_ = {center, radius}; }

    [[nodiscard]] DirectSample sampleDirect(const Vec3& ref, const Vec2& u) const override {
        (void)u;
        DirectSample ds;
        ds.wi = -d_;
        ds.p = disk_.beyond(ref, ds.wi);
        ds.n = d_;
        ds.dist = std::numeric_limits<double>::infinity();
        ds.value = irradiance_;
        ds.pdf = 1;
        return ds;
    }

    // Delta direction: the discrete choice counts as 1 (emitter.h).
    [[nodiscard]] double pdfDirect(const Vec3&, const Vec3&, const Vec3&, const Vec3&) const override { return 1; }

    // Position uniform on the scene disk perpendicular to the direction; the direction is the delta.
    [[nodiscard]] EmissionSample sampleEmission(const Vec2& uPos, const Vec2& uDir) const override {
        (void)uDir;
        EmissionSample es;
        es.p = disk_.sample(uPos, d_);
        es.n = d_;
        es.d = d_;
        es.value = irradiance_;
        es.pdfPos = disk_.pdf();
        es.pdfDir = 1;
        return es;
    }

    void pdfEmission(const Vec3&, const Vec3&, const Vec3&, double& pdfPos, double& pdfDir) const override {
        pdfPos = disk_.pdf();
        pdfDir = 1;
    }

    [[nodiscard]] Spectrum irradiance() const override { return irradiance_; }

    // The power crossing the scene's bounding disk (pbrt-v3 DistantLight::Power).
    [[nodiscard]] Spectrum power() const override { return irradiance_ * disk_.area(); }

private:
    Vec3 d_;
    Spectrum irradiance_;
    SceneDisk disk_;
};

} // namespace

std::unique_ptr<Emitter> makeDirectionalEmitter(const Vec3& direction, const Spectrum& irradiance) {
    if (!isFinite(direction) || !(lengthSquared(direction) > 0))
        throw Error("directional emitter: direction must be finite and nonzero");
    return std::make_unique<DirectionalEmitter>(direction, irradiance);
}

} // namespace lt
