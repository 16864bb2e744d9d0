#include "mcmc/mutations/portal_perturbation.h"

#include <algorithm>
#include <cmath>

#include "mcmc/mutations/trace.h"
#include "path/scatter.h"

namespace lt {

namespace {

// The direction of the edge (v[i], v[i + 1]) from its eye side toward its light side.
Vec3 edgeDirection(const std::vector<PathVertex>& v, size_t i) { return v[i + 1].directionTo(v[i]); }

} // namespace

std::optional<PortalCrossing> portalCrossing(const Scene& scene, const std::vector<PathVertex>& v) {
    if (!scene.hasPortals() || v.size() < 3) return std::nullopt;
    // Edges from the sensor toward the light, the camera's own edge (i = k - 1) left out: the camera vertex is
    // held (a pinhole, or a lens point no ray from the portal is aimed at), as are a point light and a
    // directional light's one direction (i = 0).
    // On each edge, the crossing nearest its eye-side end, on the segment's own line (a shadow ray's offset
    // ends would tilt it and move the crossing by their offset, far more than the pivot's tolerance) with
    // both ends cut by a relative 1e-6, so a vertex never crosses at its own position.
    for (size_t i = v.size() - 2; i-- > 0;) {
        if (i == 0 && v[0].isDeltaLight()) continue;
        Ray ray{v[i + 1].p(), edgeDirection(v, i)};
        const double extent = v[i].infinite ? scene.sceneRadius() : length(v[i].p() - v[i + 1].p());
        ray.tmin = 1e-6 * extent;
        if (!v[i].infinite) ray.tmax = extent * (1 - 1e-6);
        const auto hit = scene.intersectPortal(ray);
        if (!hit) continue;
        // The point from the primitive's own coordinates, in double, as every state's crossing is found.
        const RayEndpoint at = scene.shapes[size_t(hit->shape)].pointAt(hit->prim, hit->coords);
        return PortalCrossing{i, at.p, at.ng, at.magnitude};
    }
    return std::nullopt;
}

PortalPerturbation::PortalPerturbation(const Scene& scene, const ReciprocalKernel& angles)
    : scene_(scene), angles_(angles) {}

bool PortalPerturbation::suitable(const MarkovPath& x) const {
    const auto crossing = portalCrossing(scene_, x.v);
    if (!crossing) return false;
    const size_t i = crossing->edge;
    const auto& v = x.v;
    return !isSpecular(v[i]) && !isSpecular(v[i + 1]) && !isSpecular(v[i + 2]) && !(i > 0 && isSpecular(v[i - 1]));
}

double PortalPerturbation::density(const Vec3& from, const Vec3& n, const MarkovPath& to, size_t edge) const {
    const Vec3 w = edgeDirection(to.v, edge);
    const double cosPortal = std::abs(dot(n, w));
    if (!(cosPortal > 0)) return 0;
    // The angle comes back from float hit points a little off the sampled one (1e-5 relative near r_min):
    // held inside the kernel's range, so a move sampled at its end is not given density 0. Both directions
    // take it from the same two edges, so p_sigma cancels in the ratio whatever it is.
    const double theta = std::clamp(std::atan2(length(cross(from, w)), dot(from, w)), angles_.lo, angles_.hi);
    return angles_.sphereDensity(theta) / cosPortal * geometryTerm(to.v[edge], to.v[edge + 1]);
}

void PortalPerturbation::propose(const MarkovPath& x, Pcg32& rng, Proposal& out) const {
    out.reset();
    const auto crossing = portalCrossing(scene_, x.v);
    if (!crossing) {
        out.failed = RejectCause::ZeroContribution;
        return;
    }
    const size_t i = crossing->edge;
    // 1. The direction about the fixed pivot (Eq. 5), in the same half as the old one (theta <= r_max < pi/2).
    const Vec3 w0 = edgeDirection(x.v, i);
    const double theta = angles_.sample(rng.nextDouble());
    const Vec3 w = rotateDirection(w0, theta, 2 * Pi * rng.nextDouble());
    // 2. The two vertices: the first hits from the pivot backward and forward. The light side of an edge
    // that ended on a light must reach a light again (an area emitter, or the sky when the ray leaves).
    auto eyeSide = traceVertex(scene_, Ray{crossing->p, -w});
    auto lightSide = traceOrEscape(scene_, Ray{crossing->p, w}, i == 0);
    if (eyeSide && lightSide && i == 0 && !lightSide->infinite) lightSide = asLightVertex(scene_, *lightSide);
    if (!eyeSide || !lightSide) {
        out.failed = RejectCause::Missed;
        return;
    }
    // Both scatter through their non-delta lobes (as the half-vector mutation's moved vertices).
    for (PathVertex* moved : {&*eyeSide, &*lightSide})
        if (moved->bsdf) moved->lobe = moved->bsdf->lobes() & ~LobeDelta;
    out.y = x;
    out.y.v[i] = std::move(*lightSide);
    out.y.v[i + 1] = std::move(*eyeSide);
    // 3. The reverse move must turn the same edge about the same pivot (Sec. 4.5). The two pivots are found
    // from float barycentrics: they agree to a few float ulps of the portal's coordinates, more along a
    // grazing edge.
    const auto back = portalCrossing(scene_, out.y.v);
    const double slack = 1e-5 * std::max(crossing->magnitude, 1e-3 * scene_.sceneRadius()) /
                         std::max(std::abs(dot(crossing->n, w)), 1e-3);
    if (!back || back->edge != i || length(back->p - crossing->p) > slack) {
        out.failed = RejectCause::NotReversible;
        return;
    }
    // 4. Visibility of the new edges and f (evaluatePath), then T both ways (Eq. 10).
    if (!evaluateProposal(scene_, x, out)) return;
    const double sampled =
        angles_.sphereDensity(theta) / std::abs(dot(crossing->n, w)) * geometryTerm(out.y.v[i], out.y.v[i + 1]);
    setTransitionDensities(out, x, sampled, density(w0, crossing->n, out.y, i),
                           density(edgeDirection(out.y.v, i), back->n, x, i));
}

// It moves only edges that cross a portal (Otsu et al. Sec. 4.5: suitability 0 elsewhere). The paper mixes
// bidirectional : (lens : portal = 1 : 1) = 1 : 1; auto gives every chosen strategy weight 1.
const MutationKind PortalPerturbation::Kind{
    "portal",
    "perturbation",
    "turns the edge crossing a portal (a window, a door ajar) about its crossing point: light entering a room "
    "through a small opening",
    {{"--portal-range", "portal_range",
      "portal perturbation: the smallest and largest turn of the edge about its crossing, in radians (default "
      "0.00390625,0.0625: 2^-8 and 2^-4, Otsu et al.'s values)",
      "MIN,MAX", "0.00390625,0.0625",
      option::numbers(
          2, [](const std::vector<double>& r) { return r[0] > 0 && r[0] < r[1] && r[1] < Pi / 2; },
          "need 0 < MIN < MAX < pi/2 radians")}},
    [](const MutationContext& c, const OptionValues& values) -> std::unique_ptr<Mutation> {
        const auto range = values.at("portal_range").get<std::vector<double>>();
        return std::make_unique<PortalPerturbation>(c.scene, ReciprocalKernel{range[0], range[1]});
    },
    [](const SceneFeatures& f) { return f.hasPortals ? std::string() : f.portalReason; },
    {},
    [](const SceneFeatures& f) {
        return f.hasPortals ? std::string() : "portal perturbation: " + f.portalReason + " (it will propose nothing)";
    }};

} // namespace lt
