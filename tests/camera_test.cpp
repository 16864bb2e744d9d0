// The perspective camera (Mitsuba's raster <-> camera mapping, fovAxis, crop window, near clip), the thin
// lens, their importance and emission densities, and the pixel filters.
//
// Normalization checked here (Veach thesis 8.1.2, pbrt-v3 PerspectiveCamera::We): with the pinhole a
// delta position (pdfPos = 1), the integral over directions of W_e(w) cos(theta) is 1, and so is the
// integral of pdfDir(w); both are estimated with directions uniform on the sphere, within 5 standard
// errors (fixed seeds).
#include <catch2/catch.hpp>

#include <cmath>

#include "math/constants.h"
#include "util/error.h"
#include "math/rng.h"
#include "math/warp.h"
#include "scene/camera.h"

using namespace lt;

namespace {

Film makeFilm(int w, int h) {
    Film f;
    f.width = w;
    f.height = h;
    return f;
}

double angleBetween(const Vec3& a, const Vec3& b) { return radToDeg(std::acos(std::clamp(dot(a, b), -1.0, 1.0))); }

const Transform kSomeRotation =
    Transform::translate({0.5, -1, 2}) * Transform::rotate(normalize(Vec3(1, 2, -1)), 37);

} // namespace

TEST_CASE("camera: raster -> ray -> raster round trip", "[camera]") {
    Film film = makeFilm(64, 48);
    film.cropX = 10, film.cropY = 8, film.cropWidth = 30, film.cropHeight = 20;
    const PerspectiveCamera cam(kSomeRotation, 50, FovAxis::X, film, 0.1);
    Pcg32 rng(1, 0);
    for (int i = 0; i < 10000; ++i) {
        const Vec2 r{10 + 30 * rng.nextDouble(), 8 + 20 * rng.nextDouble()};
        const Ray ray = cam.generateRay(r, cam.position());
        REQUIRE(length(ray.d) == Approx(1).epsilon(1e-14));
        REQUIRE(length(ray.o - cam.position()) == 0);
        const auto back = cam.rasterPosition(cam.position(), ray.d);
        REQUIRE(back);
        REQUIRE(std::abs(back->x - r.x) < 1e-9);
        REQUIRE(std::abs(back->y - r.y) < 1e-9);
        // Near clip is a plane at distance 0.1 along the view axis.
        REQUIRE(ray.tmin * dot(ray.d, cam.forward()) == Approx(0.1).epsilon(1e-12));
        // W_e = 1 / (A cos^4) and pdfDir = 1 / (A cos^3) inside the window.
        const double c = dot(ray.d, cam.forward());
        REQUIRE(cam.importance(cam.position(), ray.d) ==
                Approx(1 / (cam.imagePlaneArea() * c * c * c * c)).epsilon(1e-12));
        double pdfPos, pdfDir;
        cam.pdfEmission(cam.position(), ray.d, pdfPos, pdfDir);
        REQUIRE(pdfPos == 1);
        REQUIRE(pdfDir == Approx(1 / (cam.imagePlaneArea() * c * c * c)).epsilon(1e-12));
    }
    // Outside the crop window (but on the film) and behind the camera: no raster position, no importance.
    const Vec3 outside = cam.generateRay({5, 5}, cam.position()).d;
    CHECK_FALSE(cam.rasterPosition(cam.position(), outside));
    CHECK(cam.importance(cam.position(), outside) == 0);
    CHECK_FALSE(cam.rasterPosition(cam.position(), -cam.forward()));
}

TEST_CASE("camera: importance and emission density integrate to one over the crop window", "[camera]") {
    Film film = makeFilm(64, 48);
    for (bool crop : {false, true}) {
        if (crop) film.cropX = 10, film.cropY = 8, film.cropWidth = 30, film.cropHeight = 20;
        const PerspectiveCamera cam(kSomeRotation, 70, FovAxis::X, film, 0);
        Pcg32 rng(2, crop);
        const int n = 400000;
        double sumW = 0, sumW2 = 0, sumP = 0, sumP2 = 0;
        for (int i = 0; i < n; ++i) {
            const double a = rng.nextDouble();
            const Vec3 d = warp::squareToUniformSphere({a, rng.nextDouble()});
            const double w = cam.importance(cam.position(), d) * std::max(0.0, dot(d, cam.forward())) /
                             warp::squareToUniformSpherePdf();
            double pdfPos, pdfDir;
            cam.pdfEmission(cam.position(), d, pdfPos, pdfDir);
            const double p = pdfDir / warp::squareToUniformSpherePdf();
            sumW += w, sumW2 += w * w, sumP += p, sumP2 += p * p;
        }
        const double mw = sumW / n, mp = sumP / n;
        const double sw = std::sqrt((sumW2 / n - mw * mw) / n), sp = std::sqrt((sumP2 / n - mp * mp) / n);
        INFO("crop " << crop << ": W_e cos integral " << mw << " +- " << sw << ", pdfDir integral " << mp
                     << " +- " << sp);
        // Normalized over the crop window, both extend over the sensor margin around it (where border
        // pixels' filters reach): the integral is the grown window's area over the window's (areas on the
        // image plane scale with raster extents).
        const double m = cam.sensorMargin();
        const double cw = crop ? 30 : 64, ch = crop ? 20 : 48;
        const double grown = (cw + 2 * m) * (ch + 2 * m) / (cw * ch);
        CHECK(std::abs(mw - grown) <= 5 * sw);
        CHECK(std::abs(mp - grown) <= 5 * sp);
    }
}

TEST_CASE("camera: fovAxis follows Mitsuba", "[camera]") {
    const double fov = 40;
    for (const auto& size : {std::pair{64, 48}, std::pair{48, 64}}) {
        const int w = size.first, h = size.second; // lambdas below capture them (clang 14: no bindings)
        const Film film = makeFilm(w, h);
        auto angleX = [&](const PerspectiveCamera& c) {
            return angleBetween(c.generateRay({0, h / 2.0}, c.position()).d,
                                c.generateRay({double(w), h / 2.0}, c.position()).d);
        };
        auto angleY = [&](const PerspectiveCamera& c) {
            return angleBetween(c.generateRay({w / 2.0, 0}, c.position()).d,
                                c.generateRay({w / 2.0, double(h)}, c.position()).d);
        };
        auto angleDiag = [&](const PerspectiveCamera& c) {
            return angleBetween(c.generateRay({0, 0}, c.position()).d,
                                c.generateRay({double(w), double(h)}, c.position()).d);
        };
        const PerspectiveCamera x(kSomeRotation, fov, FovAxis::X, film, 0);
        const PerspectiveCamera y(kSomeRotation, fov, FovAxis::Y, film, 0);
        const PerspectiveCamera diag(kSomeRotation, fov, FovAxis::Diagonal, film, 0);
        const PerspectiveCamera smaller(kSomeRotation, fov, FovAxis::Smaller, film, 0);
        const PerspectiveCamera larger(kSomeRotation, fov, FovAxis::Larger, film, 0);
        CHECK(angleX(x) == Approx(fov).epsilon(1e-12));
        CHECK(x.fovX() == Approx(fov).epsilon(1e-12));
        CHECK(angleY(y) == Approx(fov).epsilon(1e-12));
        CHECK(angleDiag(diag) == Approx(fov).epsilon(1e-12));
        // "smaller" is the axis of the smaller image side, "larger" the other.
        CHECK((w > h ? angleY(smaller) : angleX(smaller)) == Approx(fov).epsilon(1e-12));
        CHECK((w > h ? angleX(larger) : angleY(larger)) == Approx(fov).epsilon(1e-12));
    }
}

TEST_CASE("camera: cornell-box orientation", "[camera]") {
    // Mitsuba's cornell box: <matrix value="-1 0 0 0 0 1 0 1 0 0 -1 6.8 0 0 0 1"/>, fov 19.5, 512 x 512.
    Matrix4 m;
    const double v[16] = {-1, 0, 0, 0, 0, 1, 0, 1, 0, 0, -1, 6.8, 0, 0, 0, 1};
    for (int i = 0; i < 16; ++i) m.m[i / 4][i % 4] = v[i];
    const PerspectiveCamera cam(Transform::fromMatrix(m), 19.5, FovAxis::X, makeFilm(512, 512), 0.01);
    CHECK(length(cam.position() - Vec3(0, 1, 6.8)) < 1e-15);
    CHECK(length(cam.forward() - Vec3(0, 0, -1)) < 1e-15);
    // The red wall (x = -1) is on the image's left, the ceiling at the top.
    CHECK(cam.generateRay({0, 512}, cam.position()).d.x < 0);
    CHECK(cam.generateRay({0, 256}, cam.position()).d.x < 0);
    CHECK(cam.generateRay({512, 256}, cam.position()).d.x > 0);
    const Ray up = cam.generateRay({512, 0}, cam.position());
    CHECK((up.o + up.d * 5).y > 1);
    CHECK(cam.generateRay({256, 512}, cam.position()).d.y < 0);
}

TEST_CASE("camera: invalid parameters", "[camera]") {
    const Film film = makeFilm(64, 48);
    CHECK_THROWS_AS(PerspectiveCamera(Transform(), 0, FovAxis::X, film, 0), Error);
    CHECK_THROWS_AS(PerspectiveCamera(Transform(), 180, FovAxis::X, film, 0), Error);
    CHECK_THROWS_AS(PerspectiveCamera(Transform(), 45, FovAxis::X, makeFilm(0, 10), 0), Error);
    CHECK_THROWS_AS(PerspectiveCamera(Transform::scale({2, 2, 2}), 45, FovAxis::X, film, 0), Error);
    Film crop = film;
    crop.cropX = 60, crop.cropWidth = 10;
    CHECK_THROWS_AS(PerspectiveCamera(Transform(), 45, FovAxis::X, crop, 0), Error);
}

TEST_CASE("pixel filters: integrals and support", "[camera]") {
    PixelFilter box;
    PixelFilter tent;
    tent.type = PixelFilter::Type::Tent;
    tent.radius = 1;
    PixelFilter gauss;
    gauss.type = PixelFilter::Type::Gaussian;
    gauss.stddev = 0.5;
    gauss.radius = 4 * gauss.stddev;
    // Box and tent integrate to 1; the gaussian (Mitsuba 0.5: exp(-x^2 / 2 s^2) - exp(-r^2 / 2 s^2)) to
    // (s sqrt(2 pi) erf(r / (s sqrt 2)) - 2 r exp(-r^2 / 2 s^2))^2.
    CHECK(box.integral() == Approx(1).epsilon(1e-15));
    CHECK(tent.integral() == Approx(1).epsilon(1e-15));
    const double g1 = 0.5 * std::sqrt(TwoPi) * std::erf(2 / (0.5 * std::sqrt(2.0))) - 4 * std::exp(-8.0);
    CHECK(gauss.integral() == Approx(g1 * g1).epsilon(1e-12));
    CHECK(gauss.eval(0, 0) == Approx(sqr(1 - std::exp(-8.0))).epsilon(1e-12));
    for (const PixelFilter& f : {box, tent, gauss}) {
        INFO(f.name());
        // Midpoint rule on a grid fine enough for these piecewise-smooth kernels (error ~ h^2 = 1e-6).
        const int n = 2000;
        const double h = 2 * f.radius / n;
        double sum = 0;
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) sum += f.eval(-f.radius + (i + 0.5) * h, -f.radius + (j + 0.5) * h);
        CHECK(sum * h * h == Approx(f.integral()).epsilon(1e-5));
        const double beyond = f.radius * (1 + 1e-9);
        CHECK(f.eval(beyond, 0) == 0);
        CHECK(f.eval(0, -beyond) == 0);
        CHECK(f.eval(3 * f.radius, 3 * f.radius) == 0);
    }
    CHECK(box.name() == "box");
    CHECK(tent.name() == "tent");
    CHECK(gauss.name() == "gaussian");
}

TEST_CASE("thin lens: every lens point's ray of a raster position meets the focus plane at the pinhole ray's "
          "point, and back",
          "[camera]") {
    Film film = makeFilm(64, 48);
    film.cropX = 10, film.cropY = 8, film.cropWidth = 30, film.cropHeight = 20;
    const double R = 0.3, focus = 4.5;
    const PerspectiveCamera cam(kSomeRotation, 50, FovAxis::X, film, 0.1, ThinLens{R, focus});
    const PerspectiveCamera pinhole(kSomeRotation, 50, FovAxis::X, film, 0.1);
    REQUIRE(cam.hasAperture());
    CHECK(cam.lensArea() == Approx(Pi * R * R));
    Pcg32 rng(11, 0);
    for (int i = 0; i < 10000; ++i) {
        const Vec2 r{10 + 30 * rng.nextDouble(), 8 + 20 * rng.nextDouble()};
        const Vec3 lens = cam.sampleLens({rng.nextDouble(), rng.nextDouble()});
        // On the aperture: in the plane through the centre across the view axis, within R of the centre.
        REQUIRE(std::abs(dot(lens - cam.position(), cam.forward())) < 1e-12);
        REQUIRE(length(lens - cam.position()) <= R * (1 + 1e-12));
        REQUIRE(cam.onLens(lens));
        const Ray ray = cam.generateRay(r, lens);
        REQUIRE(length(ray.o - lens) == 0);
        // The pinhole ray of r reaches the focus plane (distance `focus` along the axis) at p; so does this one.
        const Ray centre = pinhole.generateRay(r, pinhole.position());
        const Vec3 p = centre.o + centre.d * (focus / dot(centre.d, cam.forward()));
        const Vec3 q = ray.o + ray.d * (focus / dot(ray.d, cam.forward()));
        REQUIRE(length(p - q) < 1e-9 * focus);
        const auto back = cam.rasterPosition(lens, ray.d);
        REQUIRE(back);
        REQUIRE(std::abs(back->x - r.x) < 1e-8);
        REQUIRE(std::abs(back->y - r.y) < 1e-8);
        REQUIRE(ray.tmin * dot(ray.d, cam.forward()) == Approx(0.1).epsilon(1e-12));
        // pbrt-v3's W_e = 1 / (A_lens A cos^4); the direction density is the pinhole's, the position's 1 / A_lens.
        const double c = dot(ray.d, cam.forward());
        REQUIRE(cam.importance(lens, ray.d) ==
                Approx(1 / (cam.lensArea() * cam.imagePlaneArea() * c * c * c * c)).epsilon(1e-12));
        double pdfPos, pdfDir;
        cam.pdfEmission(lens, ray.d, pdfPos, pdfDir);
        REQUIRE(pdfPos == Approx(1 / cam.lensArea()).epsilon(1e-12));
        REQUIRE(pdfDir == Approx(1 / (cam.imagePlaneArea() * c * c * c)).epsilon(1e-12));
    }
    CHECK_FALSE(cam.onLens(cam.position() + cam.forward() * 0.01));
    const Vec3 rim = cam.sampleLens({0.999, 0.5});
    CHECK_FALSE(cam.onLens(rim + (rim - cam.position()) * 0.1));
    // Bad lenses.
    CHECK_THROWS_AS(PerspectiveCamera(Transform(), 45, FovAxis::X, film, 0, ThinLens{-1, 1}), Error);
    CHECK_THROWS_AS(PerspectiveCamera(Transform(), 45, FovAxis::X, film, 0, ThinLens{0.1, 0}), Error);
    CHECK_THROWS_AS(PerspectiveCamera(Transform(), 45, FovAxis::X, film, 0, ThinLens{std::nan(""), 1}), Error);
}

TEST_CASE("thin lens: importance integrates to one over the aperture and the crop window's directions", "[camera]") {
    Film film = makeFilm(64, 48);
    film.cropX = 10, film.cropY = 8, film.cropWidth = 30, film.cropHeight = 20;
    const PerspectiveCamera cam(kSomeRotation, 70, FovAxis::X, film, 0, ThinLens{0.2, 3});
    // Lens points uniform on the aperture (density 1 / A_lens) and directions uniform on the sphere:
    // E[W_e cos A_lens / p_sphere] is the integral of W_e cos over lens area and directions.
    Pcg32 rng(12, 0);
    const int n = 400000;
    double sum = 0, sum2 = 0;
    for (int i = 0; i < n; ++i) {
        const Vec3 lens = cam.sampleLens({rng.nextDouble(), rng.nextDouble()});
        const double a = rng.nextDouble();
        const Vec3 d = warp::squareToUniformSphere({a, rng.nextDouble()});
        const double w = cam.importance(lens, d) * std::max(0.0, dot(d, cam.forward())) * cam.lensArea() /
                         warp::squareToUniformSpherePdf();
        sum += w, sum2 += w * w;
    }
    const double mean = sum / n, se = std::sqrt((sum2 / n - mean * mean) / n);
    const double m = cam.sensorMargin();
    const double grown = (30 + 2 * m) * (20 + 2 * m) / (30.0 * 20.0);
    INFO("integral " << mean << " +- " << se << ", expected " << grown);
    CHECK(std::abs(mean - grown) <= 5 * se);
}
