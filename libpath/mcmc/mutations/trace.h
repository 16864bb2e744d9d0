// A new eye-side vertex through a raster position uniform over the sensor window, for the path-space
// mutations; the scattering step itself is path/scatter.h.
#pragma once

#include <optional>

#include "math/rng.h"
#include "mcmc/sensor_window.h"
#include "path/scatter.h"
#include "path/vertex.h"

namespace lt {

// A new eye-side vertex seen from the camera vertex through a raster position uniform over the sensor
// window, and its density in the area measure (markov_path.h's densityFromEye at k - 1); when the ray
// escapes, nothing, or with `escape` on a scene with an environment, the environment's vertex with its
// density in solid angle.
struct TracedVertex {
    PathVertex v;
    double density = 0;
};
[[nodiscard]] std::optional<TracedVertex> traceFromCamera(const Scene& scene, const SensorWindow& sensor,
                                                          const PathVertex& camera, Pcg32& rng, bool escape = false);

// The vertex `ray` (unit direction) reaches: the surface it hits, or with `escape` on a scene with an
// environment, the environment's vertex (path/vertex.h); nothing otherwise.
[[nodiscard]] std::optional<PathVertex> traceOrEscape(const Scene& scene, const Ray& ray, bool escape);

} // namespace lt
