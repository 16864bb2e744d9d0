// One scattering step of path construction, the one place for it: BDPT's random walks, the path tracer
// and the path-space mutations (bidirectional, lens subpath) sample the world-space BSDF of a vertex here
// and trace the ray it chose to the next vertex here. The two halves are apart because BDPT decides Russian roulette
// between them (a path that stops traces no ray). Densities stay with the callers: BDPT converts the
// solid-angle pdf to area measure on the vertex it traced (PathVertex::convertDensity), the chains strip
// delta factors (mcmc/markov_path.h).
#pragma once

#include <optional>

#include "path/vertex.h"

namespace lt {

// Samples a world-space BSDF for the direction `wi` toward the previous vertex. Nothing when the BSDF
// rejects the sample (the shading-normal side test) or its weight is zero. The path tracer, which keeps
// no vertices, calls this form.
[[nodiscard]] std::optional<BsdfSample> sampleScattering(const WorldBsdf& bsdf, const Vec3& wi, Transport mode,
                                                         double uLobe, const Vec2& u);

// Samples the BSDF of surface vertex `v` (which must have one) for the direction `wi` toward the vertex
// before it, as above, and records the lobe on `v` (v.lobe, and v.delta when the lobe is a delta).
[[nodiscard]] std::optional<BsdfSample> sampleScattering(PathVertex& v, const Vec3& wi, Transport mode, double uLobe,
                                                         const Vec2& u);

// The ray leaving `from` along `dir`: offset from a surface, from the point itself for point-like
// vertices (pinhole, point light).
[[nodiscard]] Ray rayFrom(const PathVertex& from, const Vec3& dir);

// The surface vertex where `ray` first hits the scene (BSDF and emitter attached), or nothing when it
// escapes.
[[nodiscard]] std::optional<PathVertex> traceVertex(const Scene& scene, const Ray& ray);

} // namespace lt
