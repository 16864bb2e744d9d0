// The perspective sensor, Mitsuba's `perspective` (a pinhole) and `thinlens` (a thin lens: an aperture disk
// of radius R around the pinhole's position, in focus on the plane at the focus distance), with its film and
// pixel filter.
//
// The camera vertex of a path is a point on the lens (the pinhole itself when R = 0). A ray of raster
// position r leaves lens point x toward the point of the focus plane that r's pinhole ray meets; inversely
// the raster position of (x, direction) is that of the focus-plane point it reaches (pbrt-v3 6.2.3 and
// 16.1.1). Importance and densities follow pbrt-v3 PerspectiveCamera::We/Pdf_We: a lens point uniform on
// the aperture (area density 1 / A_lens) and a raster position uniform on the crop window give
// W_e(x, w) = 1 / (A_lens A cos^4 theta), the direction density 1 / (A cos^3 theta) at any lens point. A
// pinhole counts as a lens of area 1 whose only point is the pinhole (a delta position, density 1).
//
// Camera space follows Mitsuba: it looks along +z, raster x grows toward camera -x and raster y toward
// camera -y (Mitsuba's perspective.cpp cameraToSample), and toWorld places it. Raster coordinates are in
// pixels of the FULL film, (0,0) at the top-left corner; a crop window selects the pixels rendered.
#pragma once

#include <algorithm>
#include <optional>
#include <string>

#include "math/spectrum.h"
#include "math/transform.h"
#include "scene/ray.h"

namespace lt {

struct PixelFilter {
    enum class Type { Box, Tent, Gaussian };
    Type type = Type::Box;
    double radius = 0.5;     // support half-width in pixels (box 0.5, tent 1, gaussian 4 stddev)
    double stddev = 0.5;     // gaussian only
    [[nodiscard]] double eval(double dx, double dy) const;   // separable, not normalized
    // Integral of eval over the plane (box 1, tent 1, gaussian about 1.567 for stddev 0.5): a film that
    // averages with weights (sum w f / sum w, Mitsuba's hdrfilm) needs no normalization; a splatting
    // film divides by this so that each pixel's filter integrates to 1 (as the
    // Metropolis image estimator requires).
    [[nodiscard]] double integral() const;
    [[nodiscard]] std::string name() const;
};

struct Film {
    int width = 768, height = 576;              // full film size in pixels
    int cropX = 0, cropY = 0, cropWidth = 0, cropHeight = 0;   // rendered window (defaults: whole film)
    PixelFilter filter;
    std::string type = "hdrfilm";
};

enum class FovAxis { X, Y, Diagonal, Smaller, Larger };

// Mitsuba's thinlens: apertureRadius (0: a pinhole) and focusDistance along the viewing axis.
struct ThinLens {
    double apertureRadius = 0;
    double focusDistance = 1;
};

class PerspectiveCamera {
public:
    PerspectiveCamera() = default;
    // Throws lt::Error for fov outside (0, 180), a film without pixels, a crop window outside the film,
    // a negative near clip, a toWorld that scales (Mitsuba forbids it too), a negative or non-finite
    // aperture, or a focus distance that is not positive. A zero crop size means "to the film's edge" and
    // is replaced by it.
    PerspectiveCamera(const Transform& toWorld, double fovDeg, FovAxis axis, const Film& film, double nearClip,
                      const ThinLens& lens = {});

    [[nodiscard]] const Film& film() const { return film_; }
    // The pinhole, or the centre of the lens.
    [[nodiscard]] const Vec3& position() const { return position_; }
    [[nodiscard]] const ThinLens& lens() const { return lens_; }
    [[nodiscard]] bool hasAperture() const { return lens_.apertureRadius > 0; }
    // Area of the aperture; 1 for a pinhole (see above).
    [[nodiscard]] double lensArea() const { return lensArea_; }
    // A lens point uniform on the aperture (concentric disk mapping of u); the pinhole for a pinhole.
    [[nodiscard]] Vec3 sampleLens(const Vec2& u) const;
    // Whether a world point lies on the aperture disk (within round-off), for points read from files.
    [[nodiscard]] bool onLens(const Vec3& p) const;
    [[nodiscard]] const Vec3& forward() const { return forward_; }
    [[nodiscard]] double fovX() const { return fovXDeg_; }
    [[nodiscard]] double nearClip() const { return near_; }
    // The same camera on a film of another size (a tool's --resolution): the horizontal field of view
    // and the filter are kept, the crop window becomes the whole film.
    [[nodiscard]] PerspectiveCamera withResolution(int width, int height) const;

    // The ray from a lens point through a raster position (pixels of the full film).
    [[nodiscard]] Ray generateRay(const Vec2& raster, const Vec3& lensPoint) const;
    // How far beyond the crop window the sensor responds: the border pixels' centers lie half a pixel
    // inside it and their filters reach `radius` around them, so radius - 1/2 (0 for the box filter).
    // Beyond it every pixel's filter is zero.
    [[nodiscard]] double sensorMargin() const { return std::max(0.0, film_.filter.radius - 0.5); }
    // The raster position a world direction leaving a lens point maps to, if it falls inside the crop
    // window grown by sensorMargin(), in front of the camera.
    [[nodiscard]] std::optional<Vec2> rasterPosition(const Vec3& lensPoint, const Vec3& dirWorld) const;
    // Importance W_e for a direction leaving a lens point (Veach thesis 8.1.2 / pbrt-v3 PerspectiveCamera::We):
    // 1 / (A_lens A cos^4 theta) over the crop window, A the window's area on the plane at distance 1; zero
    // outside.
    [[nodiscard]] double importance(const Vec3& lensPoint, const Vec3& dirWorld) const;
    // Densities of generateRay with a lens point uniform on the aperture and a raster position uniform over
    // the crop window: pdfPos = 1 / A_lens in area, pdfDir = 1 / (A cos^3 theta) in solid angle.
    void pdfEmission(const Vec3& lensPoint, const Vec3& dirWorld, double& pdfPos, double& pdfDir) const;
    // Area of the crop window on the image plane at distance 1 from the pinhole.
    [[nodiscard]] double imagePlaneArea() const { return planeArea_; }

private:
    // The point of the plane z = 1 (camera space) that a raster position's pinhole ray crosses.
    [[nodiscard]] Vec3 planePoint(const Vec2& raster) const;

    Transform toWorld_, toCamera_;
    Film film_;
    ThinLens lens_;
    Vec3 position_, forward_;
    double fovXDeg_ = 0, tanHalfX_ = 0, tanHalfY_ = 0, planeArea_ = 0, near_ = 0, lensArea_ = 1;
};

} // namespace lt
