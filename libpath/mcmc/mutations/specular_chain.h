// Pieces shared by Veach's perturbations (lens, caustic, multi-chain; Veach thesis
// 11.4.3-11.4.4): a path is moved by perturbing one direction (or the raster position) and
// following its specular chains with the SAME lobe kind at each specular vertex, so no lobe is chosen
// and the proposal density has no lobe probability in it.
//
// Densities are delta-stripped area densities (markov_path.h): a vertex reached through a specular
// vertex with the lobe fixed has the density densityFromLight / densityFromEye divided by that lobe's
// probability, i.e. G from the light side and (R_imp / R_rad) G from the eye side.
#pragma once

#include <cmath>
#include <optional>
#include <vector>

#include "bsdf/bsdf.h"
#include "math/constants.h"
#include "math/rng.h"
#include "mcmc/markov_path.h"
#include "mcmc/mutation.h"
#include "mcmc/sensor_window.h"

namespace lt {

// A length (raster radius or angle) with density 1 / (x ln(hi / lo)) on [lo, hi]: Veach's perturbation
// sizes, spread evenly over orders of magnitude (thesis 11.4.3).
struct ReciprocalKernel {
    double lo = 0, hi = 0;

    [[nodiscard]] double sample(double u) const { return hi * std::exp(-std::log(hi / lo) * u); }
    // A relative slack of 1e-9 at the ends keeps the samples of sample() (rounded) inside.
    [[nodiscard]] double density(double x) const {
        return x >= lo * (1 - 1e-9) && x <= hi * (1 + 1e-9) ? 1 / (x * std::log(hi / lo)) : 0.0;
    }
    // Density of an offset of length r in the plane, the angle uniform: density(r) / (2 pi r).
    [[nodiscard]] double planeDensity(double r) const { return density(r) / (2 * Pi * r); }
    // Density in solid angle of a direction at angle theta from the old one, the azimuth uniform:
    // density(theta) / (2 pi sin theta).
    [[nodiscard]] double sphereDensity(double theta) const { return density(theta) / (2 * Pi * std::sin(theta)); }
};

// The unit direction at angle theta from `dir`, at azimuth phi around it.
[[nodiscard]] Vec3 rotateDirection(const Vec3& dir, double theta, double phi);

// Veach's raster radii for an image of the crop window's size: r1 = 0.1 px, r2 = sqrt(0.05 W H / pi) px
// (a disk of 5 % of the image, after Mitsuba's "jump sizes recommended by Veach").
[[nodiscard]] ReciprocalKernel rasterRadii(const PerspectiveCamera& camera);

// The scattering kind of a vertex: LobeReflection or LobeTransmission.
[[nodiscard]] inline Lobes scatterKind(const PathVertex& v) { return v.lobe & (LobeReflection | LobeTransmission); }

// The delta lobe of kind `kind` at surface vertex v for the direction wi (world, away from v): its
// sample (world wo, weight, lobe probability in pdf); nothing when v has no such lobe for wi (no delta
// lobe, total internal reflection, a side test fails).
[[nodiscard]] std::optional<BsdfSample> deltaLobe(const PathVertex& v, const Vec3& wi, Lobes kind, Transport mode);

// Delta-stripped area densities of vertex i with the lobe of a specular neighbour fixed: densityFromEye
// (from v[i + 1]) and densityFromLight (from v[i - 1]) divided by that vertex's lobe probability.
[[nodiscard]] double fixedLobeDensityFromEye(const Scene& scene, const SensorWindow& sensor,
                                             const std::vector<PathVertex>& v, size_t i);
[[nodiscard]] double fixedLobeDensityFromLight(const Scene& scene, const std::vector<PathVertex>& v, size_t i);

// Follow `ray`, which leaves the new vertex v[from] with solid-angle density pdfDir, through the
// vertices from + step .. to - step (step = +-1) that are specular in `old`, each on the same shape and
// scattering through the delta lobe of the same kind (transport `mode`: Importance toward the eye,
// Radiance toward the light), to a vertex at `to` that can scatter through a non-delta lobe. Writes
// the new vertices into v and multiplies `density` by the stripped area density of each
// (markov_path.h). A missed or different vertex is RejectCause::ConfigurationChanged.
[[nodiscard]] std::optional<RejectCause> followChain(const Scene& scene, const std::vector<PathVertex>& old,
                                                     std::vector<PathVertex>& v, int from, int to, const Ray& ray,
                                                     double pdfDir, Transport mode, double& density);

// The lens perturbation's first step, shared with the multi-chain
// perturbation: a raster position at distance r from `raster` (density pOffset per unit raster area)
// and the camera ray through it with its solid-angle density; nothing when it leaves the sensor window.
// A thin lens's point moves too (a pinhole's stays): with probability 1/2 to a point uniform on the
// aperture, otherwise uniformly within a tenth of the aperture's radius of `lens` (nothing when that
// leaves the aperture). The kernel is symmetric, so it cancels from T(x -> y) / T(y -> x) as p_offset
// does; without it a chain would keep the lens point it started with.
struct CameraPerturbation {
    Ray ray; // from the new lens point
    double pOffset = 0, pdfDir = 0;
};
[[nodiscard]] std::optional<CameraPerturbation> perturbCamera(const PerspectiveCamera& camera,
                                                              const SensorWindow& sensor,
                                                              const ReciprocalKernel& radius, const Vec2& raster,
                                                              const Vec3& lens, Pcg32& rng);
// Steps 2 and 3 of the lens perturbation, also the multi-chain perturbation's start: perturb the camera
// ray, then follow x's eye-side specular chain to vertex `to` into out.y (a copy of x), multiplying
// `sampled`. Returns the raster offset's density, or nothing with out.failed set.
[[nodiscard]] std::optional<double> perturbLensChain(const Scene& scene, const SensorWindow& sensor,
                                                     const ReciprocalKernel& radius, const MarkovPath& x, int to,
                                                     Pcg32& rng, Proposal& out, double& sampled);
// The density of the eye end's vertices k - 1 .. j given the raster position (the chain behind the
// camera, lobes fixed): the sensor window's area (raster to the uniform density of densityFromEye) times
// the fixed-lobe densities from the eye.
[[nodiscard]] double eyeChainDensity(const Scene& scene, const SensorWindow& sensor, const std::vector<PathVertex>& v,
                                     int j);

// Radians per pixel at the image center: sqrt(crop window's area on the image plane / its pixels).
[[nodiscard]] double radiansPerPixel(const PerspectiveCamera& camera);

// The first non-specular vertex seen from the camera through the specular vertices in front of it
// (Veach's x_j of the lens perturbation); 0 when it would be the light vertex.
[[nodiscard]] int firstNonSpecularFromEye(const std::vector<PathVertex>& v);

} // namespace lt
