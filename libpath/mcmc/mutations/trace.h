// Tracing new path vertices for the path-space mutations: the one place that turns a ray hit into a
// PathVertex (BSDF and emitter attached) and a vertex plus a direction into a ray.
#pragma once

#include <optional>

#include "math/rng.h"
#include "mcmc/sensor_window.h"
#include "path/vertex.h"

namespace lt {

// The surface vertex where `ray` first hits the scene, or nothing when it escapes.
[[nodiscard]] std::optional<PathVertex> traceVertex(const Scene& scene, const Ray& ray);

// The ray leaving `from` along `dir`: offset from a surface, from the point itself for point-like
// vertices (pinhole, point light).
[[nodiscard]] Ray rayFrom(const PathVertex& from, const Vec3& dir);

// A new eye-side vertex seen from the camera vertex through a raster position uniform over the sensor
// window, and its density in the area measure (markov_path.h's densityFromEye at k - 1); nothing when
// the ray escapes.
struct TracedVertex {
    PathVertex v;
    double density = 0;
};
[[nodiscard]] std::optional<TracedVertex> traceFromCamera(const Scene& scene, const SensorWindow& sensor,
                                                          const PathVertex& camera, Pcg32& rng);

} // namespace lt
