// The state of a path-space Markov chain (Veach and Guibas 1997): a whole light path, light
// to eye, with everything the mutations need to evaluate it and the densities of re-sampling its
// vertices. evaluatePath() recomputes the contribution from the vertices alone (as Mitsuba's
// verification.cpp re-checks a path); nothing cached survives a proposal unchecked.
//
// Specular vertices. A vertex that scattered through a delta lobe makes f a distribution: f_s = R
// delta_perp, with delta_perp the Dirac delta in projected solid angle at the vertex (geometric normal)
// and R = (lobe weight) x (lobe probability) as WorldBsdf::deltaEval reports it. Every path a chain
// compares shares the same deltas (mutations keep or re-sample them together with their densities), so
// lt strips each delta_perp, in light-to-eye orientation, from f and from the densities alike:
// * f~ keeps R (importance transport, wi toward the light) and all geometry terms;
// * a vertex sampled from the light side through a specular vertex has density prob G (prob: the lobe's
//   discrete probability);
// * one sampled from the eye side through it has density (R_imp / weight_rad) G: the delta of the
//   reverse direction differs from the light-to-eye one by R_rad / R_imp (refraction scales projected
//   solid angle by eta^2, Veach thesis 5.2), which is exactly what BDPT's throughput weights encode.
// Ratios f~ / p~ then equal BDPT's f / p for every strategy, and f~ / f~* = f / f* for the image.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "bsdf/bsdf.h"
#include "formats/records.h"
#include "mcmc/image_contribution.h"
#include "mcmc/mutation_statistics.h"
#include "mcmc/sensor_window.h"
#include "path/vertex.h"

namespace lt {

struct MarkovPath {
    std::vector<PathVertex> v; // light to eye: v[0] a light vertex, v.back() the camera vertex
    Vec2 raster;               // where the last edge meets the image plane (pixels of the full film)
    Spectrum f;                // f~ in image units: (crop pixels) x f, specular deltas stripped
    double target = 0;         // f* = targetValue(f)

    [[nodiscard]] int edges() const { return int(v.size()) - 1; }
    // The image contribution: f at the raster position (splatted with the pixel filter).
    [[nodiscard]] std::vector<ImageContribution> contribution() const { return {{raster, f}}; }
};

// A chain's target function other than luminance (GDMLT's gradient target, gdmlt/chain_gradient.h): f* of a
// path from its vertices (light to eye), raster position and f, positive wherever f is not black (a target that
// is 0 where f is not would bias the image). Empty: targetValue(f), which evaluatePath sets.
using PathTarget = std::function<double(const std::vector<PathVertex>& v, const Vec2& raster, const Spectrum& f)>;

// Scattered through a delta lobe (the path's configuration at that vertex).
[[nodiscard]] inline bool isSpecular(const PathVertex& v) { return v.type == VertexType::Surface && v.delta; }

// Recompute raster, f and target from the vertices alone (and set every surface vertex's wi toward the
// light side). Returns the cause when the path carries nothing: occluded, off the sensor, or zero.
// `verified`, when given, is a state evaluated before (the chain's current path): an edge of `path`
// between the same two vertices as one of its edges (same points and normals, so the same shadow ray)
// is known to be unoccluded and is not traced again. Everything else is recomputed.
[[nodiscard]] std::optional<RejectCause> evaluatePath(const Scene& scene, MarkovPath& path,
                                                      const MarkovPath* verified = nullptr);

// A chain's state as a path record (lt-mutate --dump-paths): s = t = 0 (no BDPT technique), the lobe
// bits saying exactly which vertices are specular, contribution f, weight f*, and (chain, mutation) as
// (rngStream, rngOffset). pathFromRecord reads it back.
[[nodiscard]] file::PathRecord toPathRecord(const Scene& scene, const MarkovPath& path, uint64_t chain,
                                            uint64_t mutation);

// A chain's state as the chain-state stream holds it (lt-mutate --stream, file::ChainState): what re-creates
// its vertices (the lobe bits mark the specular ones exactly, as in toPathRecord), raster, f, f* and the
// credit the image gave it.
// `out`'s storage is reused: the chains fill one record per state they credit.
void toChainState(const MarkovPath& path, uint32_t chain, double credit, file::ChainState& out);

// The path of a stored seed record (lt-seed --paths), re-created in `scene` from shape, primitive and
// barycentrics, then evaluated. Throws lt::Error naming the record when it does not fit the scene.
[[nodiscard]] MarkovPath pathFromRecord(const Scene& scene, const file::PathRecord& record, size_t index);

struct ManifoldVertex;
// Move surface vertex v to where a manifold walk left it (m's shape, primitive and coordinates, the
// surface re-created there), keeping the lobe it scattered by and whether that was a delta.
void moveVertex(const Scene& scene, const ManifoldVertex& m, PathVertex& v);

// Densities of re-sampling vertex i (delta-stripped, area measure, or solid angle for a light vertex at
// infinity; BDPT's pdf_fwd / pdf_rev): from the light side (i = 0: choosing the light point or the sky's
// direction, a directional light's choice alone; i = 1: emission from v[0]; otherwise scattering at
// v[i-1] given v[i-2]) and from the eye side (scattering at v[i+1] given v[i+2]; i = k - 1: the camera
// ray, uniform over the sensor window; i = k: a thin lens's point, uniform on the aperture). Zero where the
// vertex cannot be sampled that way (the camera vertex from the light side).
[[nodiscard]] double densityFromLight(const Scene& scene, const std::vector<PathVertex>& v, size_t i);
[[nodiscard]] double densityFromEye(const Scene& scene, const SensorWindow& sensor, const std::vector<PathVertex>& v,
                                    size_t i);

// The delta lobe at specular vertex v[i] for light-to-eye importance transport (from v[i-1] toward
// v[i+1]): its value and its lobe probability (pdf); nothing when the directions do not fit a lobe.
[[nodiscard]] std::optional<BsdfSample> deltaImportance(const std::vector<PathVertex>& v, size_t i);

// The stripped density of a vertex sampled from the eye side through a delta lobe, (R_imp / weight_rad) G
// (header comment): `imp` is the lobe for light-to-eye importance transport (weight x probability = R_imp),
// `rad` the one sampled in radiance transport (its weight includes 1 / its probability, so the density
// includes the lobe choice), g the geometry term of the new edge.
[[nodiscard]] inline double eyeSideDeltaDensity(const BsdfSample& imp, const BsdfSample& rad, double g) {
    const double weight = rad.weight.luminance();
    return weight > 0 ? (imp.weight * imp.pdf).luminance() / weight * g : 0.0;
}

} // namespace lt
