#include "mcmc/mutations/trace.h"

namespace lt {

std::optional<PathVertex> traceOrEscape(const Scene& scene, const Ray& ray, bool escape) {
    auto hit = traceVertex(scene, ray);
    if (!hit && escape && !scene.environmentEmitters.empty()) return environmentVertex(scene, ray.o, ray.d);
    return hit;
}

std::optional<TracedVertex> traceFromCamera(const Scene& scene, const SensorWindow& sensor, const PathVertex& camera,
                                            Pcg32& rng, bool escape) {
    const Vec2 raster = sensor.raster(Vec2(rng.nextDouble(), rng.nextDouble()));
    const Ray ray = scene.camera.generateRay(raster, camera.si.p);
    auto hit = traceOrEscape(scene, ray, escape);
    if (!hit) return std::nullopt;
    double pdfPos = 0, pdfDir = 0;
    scene.camera.pdfEmission(camera.si.p, ray.d, pdfPos, pdfDir);
    const double density = camera.convertDensity(pdfDir * sensor.cropToSensorDensity(), *hit);
    return TracedVertex{std::move(*hit), density};
}

} // namespace lt
