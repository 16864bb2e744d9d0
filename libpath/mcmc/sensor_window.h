// Where the sensor responds: the crop window grown by the camera's sensorMargin() (where some pixel's
// filter is non-zero), in raster pixels of the full film. Chains that pick camera rays themselves pick
// them uniformly over it.
#pragma once

#include "scene/camera.h"

namespace lt {

struct SensorWindow {
    double x0 = 0, y0 = 0, width = 0, height = 0;

    explicit SensorWindow(const PerspectiveCamera& camera) {
        const auto& f = camera.film();
        const double r = camera.sensorMargin();
        x0 = f.cropX - r;
        y0 = f.cropY - r;
        width = f.cropWidth + 2 * r;
        height = f.cropHeight + 2 * r;
        cropArea_ = double(f.cropWidth) * double(f.cropHeight);
    }
    [[nodiscard]] Vec2 raster(const Vec2& u) const { return {x0 + u.x * width, y0 + u.y * height}; }
    [[nodiscard]] double area() const { return width * height; }
    // PerspectiveCamera::pdfEmission is normalized over the crop window; a raster position uniform over
    // the whole sensor has that density times this factor.
    [[nodiscard]] double cropToSensorDensity() const { return cropArea_ / area(); }

private:
    double cropArea_ = 0;
};

} // namespace lt
