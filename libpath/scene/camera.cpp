#include "scene/camera.h"

#include <cmath>

#include "math/constants.h"
#include "util/error.h"
#include "math/numeric.h"
#include "math/rigid.h"
#include "math/warp.h"

namespace lt {

namespace {

// One axis of a separable filter (Mitsuba 0.5 src/rfilters): box of half-width r; tent max(0, 1 - |x|/r)
// with r = 1; gaussian exp(-x^2 / 2 sigma^2) minus its value at the radius r = 4 sigma, so that it
// reaches zero continuously there.
double filter1D(const PixelFilter& f, double x) {
    const double ax = std::abs(x);
    if (ax > f.radius) return 0;
    switch (f.type) {
    case PixelFilter::Type::Box:
        return 1;
    case PixelFilter::Type::Tent:
        return 1 - ax / f.radius;
    case PixelFilter::Type::Gaussian: {
        const double alpha = -1 / (2 * f.stddev * f.stddev);
        return std::max(0.0, std::exp(alpha * x * x) - std::exp(alpha * f.radius * f.radius));
    }
    }
    return 0;
}

// Integral of filter1D over the real line.
double filter1DIntegral(const PixelFilter& f) {
    switch (f.type) {
    case PixelFilter::Type::Box:
        return 2 * f.radius;
    case PixelFilter::Type::Tent:
        return f.radius;
    case PixelFilter::Type::Gaussian: {
        const double s = f.stddev, r = f.radius;
        return s * std::sqrt(TwoPi) * std::erf(r / (s * std::sqrt(2.0))) - 2 * r * std::exp(-r * r / (2 * s * s));
    }
    }
    return 0;
}

} // namespace

double PixelFilter::eval(double dx, double dy) const { return filter1D(*this, dx) * filter1D(*this, dy); }

double PixelFilter::integral() const { return sqr(filter1DIntegral(*this)); }

std::string PixelFilter::name() const {
    switch (type) {
    case Type::Box:
        return "box";
    case Type::Tent:
        return "tent";
    case Type::Gaussian:
        return "gaussian";
    }
    return "box";
}

PerspectiveCamera::PerspectiveCamera(const Transform& toWorld, double fovDeg, FovAxis axis, const Film& film,
                                     double nearClip, const ThinLens& lens)
    : toWorld_(toWorld), toCamera_(toWorld.inverse()), film_(film), lens_(lens), near_(nearClip) {
    if (film_.width <= 0 || film_.height <= 0) throw Error("film has no pixels");
    if (film_.cropWidth <= 0) film_.cropWidth = film_.width - film_.cropX;
    if (film_.cropHeight <= 0) film_.cropHeight = film_.height - film_.cropY;
    if (film_.cropX < 0 || film_.cropY < 0 || film_.cropWidth <= 0 || film_.cropHeight <= 0 ||
        film_.cropX + film_.cropWidth > film_.width || film_.cropY + film_.cropHeight > film_.height)
        throw Error("film crop window lies outside the film");
    if (!(fovDeg > 0 && fovDeg < 180)) throw Error("camera fov must be in (0, 180) degrees");
    if (!(nearClip >= 0) || !std::isfinite(nearClip)) throw Error("camera nearClip must be finite and >= 0");
    if (!isRigid(toWorld)) throw Error("camera toWorld must not scale (Mitsuba: no scale factors allowed)");
    if (!(lens.apertureRadius >= 0) || !std::isfinite(lens.apertureRadius))
        throw Error("apertureRadius must be finite and >= 0");
    if (!(lens.focusDistance > 0) || !std::isfinite(lens.focusDistance))
        throw Error("focusDistance must be finite and > 0");
    if (hasAperture()) lensArea_ = Pi * sqr(lens.apertureRadius);

    // Mitsuba's PerspectiveCamera::configure: the aspect ratio is that of the full film; "smaller" and
    // "larger" pick y or x by it, and every axis is converted to the horizontal field of view.
    const double aspect = double(film_.width) / film_.height;
    if (axis == FovAxis::Smaller) axis = aspect > 1 ? FovAxis::Y : FovAxis::X;
    if (axis == FovAxis::Larger) axis = aspect > 1 ? FovAxis::X : FovAxis::Y;
    const double tanHalf = std::tan(0.5 * degToRad(fovDeg));
    switch (axis) {
    case FovAxis::Y:
        tanHalfX_ = tanHalf * aspect;
        break;
    case FovAxis::Diagonal:
        tanHalfX_ = tanHalf / std::sqrt(1 + 1 / (aspect * aspect));
        break;
    default:
        tanHalfX_ = tanHalf;
        break;
    }
    tanHalfY_ = tanHalfX_ / aspect;
    fovXDeg_ = radToDeg(2 * std::atan(tanHalfX_));
    planeArea_ = (2 * tanHalfX_ * film_.cropWidth / film_.width) * (2 * tanHalfY_ * film_.cropHeight / film_.height);
    position_ = toWorld_.point({0, 0, 0});
    forward_ = normalize(toWorld_.vector({0, 0, 1}));
}

// Mitsuba's cameraToSample, written out: the plane z = 1 spans [-tanX, tanX] x [-tanY, tanY] and a
// raster position r (pixels of the full film) sits at x = (1 - 2 r.x / W) tanX, y = (1 - 2 r.y / H) tanY,
// so raster x grows toward camera -x and raster y toward camera -y.
Vec3 PerspectiveCamera::planePoint(const Vec2& raster) const {
    return {(1 - 2 * raster.x / film_.width) * tanHalfX_, (1 - 2 * raster.y / film_.height) * tanHalfY_, 1};
}

Vec3 PerspectiveCamera::sampleLens(const Vec2& u) const {
    if (!hasAperture()) return position_;
    const Vec2 d = warp::squareToUniformDiskConcentric(u) * lens_.apertureRadius;
    return toWorld_.point({d.x, d.y, 0});
}

bool PerspectiveCamera::onLens(const Vec3& p) const {
    const Vec3 local = toCamera_.point(p);
    const double tolerance = 1e-6 * std::max(1.0, length(position_)) + 1e-6 * lens_.apertureRadius;
    return std::abs(local.z) <= tolerance && std::hypot(local.x, local.y) <= lens_.apertureRadius + tolerance;
}

// Thin lens (Mitsuba thinlens.cpp sampleRay, pbrt-v3 6.2.3): the pinhole ray of the raster position meets
// the focus plane z = focusDistance, and the ray from the lens point aims there. A pinhole aims along the
// pinhole ray itself.
Ray PerspectiveCamera::generateRay(const Vec2& raster, const Vec3& lensPoint) const {
    Vec3 local = planePoint(raster);
    Vec3 origin = position_;
    if (hasAperture()) {
        const Vec3 lensLocal = toCamera_.point(lensPoint);
        local = local * lens_.focusDistance - Vec3(lensLocal.x, lensLocal.y, 0);
        origin = lensPoint;
    }
    local = normalize(local);
    Ray ray;
    ray.o = origin;
    ray.d = normalize(toWorld_.vector(local));
    // The near clip is a plane at z = near (Mitsuba: mint = nearClip / d.z).
    ray.tmin = near_ / local.z;
    return ray;
}

std::optional<Vec2> PerspectiveCamera::rasterPosition(const Vec3& lensPoint, const Vec3& dirWorld) const {
    Vec3 local = toCamera_.vector(dirWorld);
    if (!(local.z > 0)) return std::nullopt;
    if (hasAperture()) {
        // The focus-plane point the ray reaches, seen from the lens centre.
        const Vec3 lensLocal = toCamera_.point(lensPoint);
        local = Vec3(lensLocal.x, lensLocal.y, 0) + local * (lens_.focusDistance / local.z);
    }
    const Vec2 r{0.5 * film_.width * (1 - local.x / (local.z * tanHalfX_)),
                 0.5 * film_.height * (1 - local.y / (local.z * tanHalfY_))};
    // The sensor responds where some pixel's filter does (sensorMargin): its camera samples land there,
    // and light tracing must be able to reach the same raster positions or the MIS weights there would
    // credit a strategy that cannot sample them.
    const double m = sensorMargin();
    if (!(r.x >= film_.cropX - m && r.x < film_.cropX + film_.cropWidth + m && r.y >= film_.cropY - m &&
          r.y < film_.cropY + film_.cropHeight + m))
        return std::nullopt;
    return r;
}

// pbrt-v3 PerspectiveCamera::We: a raster position uniform on the crop window has area density 1/A on the
// plane z = 1, i.e. solid-angle density 1/(A cos^3) (dA = dw / cos^3 at distance 1/cos); for a thin lens the
// same holds at every lens point (the focus plane is the plane z = 1 scaled). W_e is normalized so that the
// integral of W_e cos over the lens and the crop window's directions is 1 (Veach thesis 8.1.2), hence
// W_e = 1/(A_lens A cos^4): a light path then contributes 1/N of a pixel's worth per pixel of the window
// (image/film.h). Both extend, unchanged, over the filter margin around the window (rasterPosition).
double PerspectiveCamera::importance(const Vec3& lensPoint, const Vec3& dirWorld) const {
    if (!rasterPosition(lensPoint, dirWorld)) return 0;
    const double cosTheta = dot(normalize(dirWorld), forward_);
    return 1 / (lensArea_ * planeArea_ * sqr(sqr(cosTheta)));
}

void PerspectiveCamera::pdfEmission(const Vec3& lensPoint, const Vec3& dirWorld, double& pdfPos, double& pdfDir) const {
    pdfPos = 1 / lensArea_;
    if (!rasterPosition(lensPoint, dirWorld)) {
        pdfDir = 0;
        return;
    }
    const double cosTheta = dot(normalize(dirWorld), forward_);
    pdfDir = 1 / (planeArea_ * cosTheta * cosTheta * cosTheta);
}

PerspectiveCamera PerspectiveCamera::withResolution(int width, int height) const {
    Film f = film_;
    f.width = width;
    f.height = height;
    f.cropX = f.cropY = 0;
    f.cropWidth = width;
    f.cropHeight = height;
    return PerspectiveCamera(toWorld_, fovXDeg_, FovAxis::X, f, near_, lens_);
}

} // namespace lt
