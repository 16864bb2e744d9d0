// Mitsuba's `envmap` emitter: radiance at infinity from a latitude-longitude image.
//
// Mapping: Mitsuba's latitude-longitude one (lat_long.h) of a direction v toward the sky in the emitter's
// local frame (+y up, v = toWorld^-1 dir): image coordinates u = phi / 2pi, t = theta / pi.
//
// Lookups are piecewise constant (the texel containing (u, t)), where Mitsuba filters bilinearly: the
// radiance is then exactly the function the piecewise-constant sampling density below follows, so
// L / p stays bounded, power() is exact, and a constant image reproduces the constant emitter.
#include <cmath>
#include <filesystem>
#include <limits>
#include <vector>

#include "math/constants.h"
#include "util/error.h"
#include "math/rigid.h"
#include "scene/emitter.h"
#include "scene/emitters/lat_long.h"
#include "scene/emitters/scene_disk.h"
#include "texture/image_file.h"

namespace lt {

namespace {

class EnvmapEmitter final : public Emitter {
public:
    EnvmapEmitter(LatLongImage image, const Transform& toWorld, double scale, std::string type)
        : toWorld_(toWorld), toLocal_(toWorld.inverse()), scale_(scale), width_(image.width), height_(image.height),
          pixels_(std::move(image.pixels)), type_(std::move(type)) {
        if (!isRigid(toWorld)) throw Error(type_ + " toWorld must be a rotation");
        // Importance: luminance times sin(theta) at the row center (Mitsuba's row weights), so that the
        // density in (u, t) follows L dw = L sin(theta) dtheta dphi.
        std::vector<double> weights(size_t(width_) * size_t(height_));
        for (int y = 0; y < height_; ++y) {
            const double sinTheta = std::sin((y + 0.5) * Pi / height_);
            const double cosTop = std::cos(y * Pi / height_), cosBottom = std::cos((y + 1) * Pi / height_);
            const double texelSolidAngle = (TwoPi / width_) * (cosTop - cosBottom);
            for (int x = 0; x < width_; ++x) {
                const Spectrum& L = texel(x, y);
                weights[size_t(y) * width_ + x] = std::max(0.0, L.luminance()) * sinTheta;
                skyIntegral_ += L * (scale_ * texelSolidAngle);
            }
        }
        distribution_ = Distribution2D(weights, width_, height_);
        if (distribution_.empty())
            throw Error((type_ == "envmap" ? "the environment map" : "the " + type_) + " is completely black");
    }

    [[nodiscard]] uint8_t flags() const override { return EmitterInfinite; }
    [[nodiscard]] std::string typeName() const override { return type_; }
    void setSceneBounds(const Vec3& center, double radius) override { disk_ = {center, radius}; }

    [[nodiscard]] DirectSample sampleDirect(const Vec3& ref, const Vec2& u) const override {
        DirectSample ds;
        ds.wi = sampleSky(u);
        // Density and radiance from the direction itself, the way pdfDirect and evalEnvironment see it,
        // so the three agree bit for bit even where round-off moves a sample across a texel edge.
        ds.pdf = pdfSky(ds.wi);
        if (!(ds.pdf > 0)) return {};
        ds.p = disk_.beyond(ref, ds.wi);
        ds.n = -ds.wi;
        ds.dist = std::numeric_limits<double>::infinity();
        ds.value = evalEnvironment(ds.wi);
        return ds;
    }

    [[nodiscard]] double pdfDirect(const Vec3&, const Vec3&, const Vec3&, const Vec3& dir) const override {
        return pdfSky(dir);
    }

    // Direction first (light travels along -sky direction), then a position on the scene disk
    // perpendicular to it (pbrt-v3 InfiniteAreaLight::Sample_Le; Mitsuba's sampleRay does the same).
    [[nodiscard]] EmissionSample sampleEmission(const Vec2& uPos, const Vec2& uDir) const override {
        EmissionSample es;
        const Vec3 sky = sampleSky(uDir);
        es.pdfDir = pdfSky(sky);
        if (!(es.pdfDir > 0)) return {};
        es.d = -sky;
        es.p = disk_.sample(uPos, es.d);
        es.n = es.d;
        es.value = evalEnvironment(sky);
        es.pdfPos = disk_.pdf();
        return es;
    }

    void pdfEmission(const Vec3&, const Vec3&, const Vec3& d, double& pdfPos, double& pdfDir) const override {
        pdfPos = disk_.pdf();
        pdfDir = pdfSky(-d);
    }

    [[nodiscard]] Spectrum evalEnvironment(const Vec3& dir) const override {
        const auto [x, y] = latLongTexel(normalize(toLocal_.vector(dir)), width_, height_);
        return texel(x, y) * scale_;
    }

    // Exact for the piecewise-constant radiance: pi r^2 times the integral of L over the sphere.
    [[nodiscard]] Spectrum power() const override { return skyIntegral_ * disk_.area(); }

private:
    [[nodiscard]] const Spectrum& texel(int x, int y) const { return pixels_[size_t(y) * width_ + x]; }

    // World direction toward the sky -> (u, t) in [0,1]^2.
    [[nodiscard]] Vec2 toImage(const Vec3& dirWorld) const {
        return latLongCoordinates(normalize(toLocal_.vector(dirWorld)));
    }

    // A world direction toward the sky, by the image distribution.
    [[nodiscard]] Vec3 sampleSky(const Vec2& u) const {
        double pdfUv;
        const Vec2 uv = distribution_.sample(u, pdfUv);
        return normalize(toWorld_.vector(skyDirection({Pi * uv.y, TwoPi * uv.x})));
    }

    // Solid-angle density of sampleSky: p(u, t) / (2 pi^2 sin theta), from dw = sin(theta) dtheta dphi
    // with dtheta = pi dt and dphi = 2 pi du. Zero at the poles, where the map is singular.
    [[nodiscard]] double pdfSky(const Vec3& dirWorld) const {
        const Vec2 uv = toImage(dirWorld);
        const double sinTheta = std::sin(Pi * uv.y);
        if (!(sinTheta > 0)) return 0;
        return distribution_.pdf(uv) / (2 * Pi * Pi * sinTheta);
    }

    Transform toWorld_, toLocal_;
    double scale_;
    int width_ = 0, height_ = 0;
    std::vector<Spectrum> pixels_;
    Distribution2D distribution_;
    Spectrum skyIntegral_;   // integral of the scaled radiance over the sphere of directions
    SceneDisk disk_;
    std::string type_;
};

// RGB from the first three channels; a gray image fills all three.
LatLongImage readLatLongImage(const std::string& filename) {
    if (!std::filesystem::exists(filename)) throw Error(filename + ": file not found");
    const ImageFile file = readImageFile(filename);
    LatLongImage image{file.width, file.height, {}};
    const int channels = file.channels;
    image.pixels.resize(size_t(image.width) * size_t(image.height));
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            const float* px = &file.pixels[(size_t(y) * image.width + x) * channels];
            const Spectrum v = channels >= 3 ? Spectrum(px[0], px[1], px[2]) : Spectrum(px[0]);
            if (!v.isFinite())
                throw Error(filename + ": pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                            ") is NaN or infinite");
            image.pixels[size_t(y) * image.width + x] = v;
        }
    return image;
}

} // namespace

std::unique_ptr<Emitter> makeEnvmapEmitter(const std::string& filename, const Transform& toWorld, double scale) {
    try {
        return std::make_unique<EnvmapEmitter>(readLatLongImage(filename), toWorld, scale, "envmap");
    } catch (const Error& e) {
        const std::string what = e.what();
        if (what.rfind(filename, 0) == 0) throw;
        throw Error(filename + ": " + what);
    }
}

std::unique_ptr<Emitter> makeEnvmapEmitter(LatLongImage image, const Transform& toWorld, const std::string& type) {
    return std::make_unique<EnvmapEmitter>(std::move(image), toWorld, 1.0, type);
}

} // namespace lt
