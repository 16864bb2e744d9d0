#include "mcmc/mutations/portal_perturbation.h"

#include <cmath>

#include "mcmc/mutations/trace.h"
#include "path/scatter.h"

namespace lt {

namespace {

// Whether the edge (v[i], v[i + 1]) can turn about a point between its ends: both vertices are re-found by
// rays from that point, which never meet a pinhole, a point light or a directional light's one direction.
bool movableEdge(const std::vector<PathVertex>& v, size_t i) {
    return v[i + 1].type == VertexType::Surface && !(i == 0 && v[0].isDeltaLight());
}

// The direction of the edge (v[i], v[i + 1]) from its eye side toward its light side.
Vec3 edgeDirection(const std::vector<PathVertex>& v, size_t i) { return v[i + 1].directionTo(v[i]); }

} // namespace

std::optional<PortalCrossing> portalCrossing(const Scene& scene, const std::vector<PathVertex>& v) {
    if (!scene.hasPortals() || v.size() < 3) return std::nullopt;
    // Edges from the sensor toward the light (the camera's own edge, i = k - 1, never moves); on each, the
    // crossing nearest its eye-side end.
    for (size_t i = v.size() - 2; i-- > 0;) {
        if (!movableEdge(v, i)) continue;
        const PathVertex& eye = v[i + 1];
        const PathVertex& light = v[i];
        Ray ray{eye.p(), edgeDirection(v, i)};
        if (!light.infinite) ray.tmax = length(light.p() - eye.p());
        const auto hit = scene.intersectPortal(ray);
        if (!hit) continue;
        const Vec3 p = ray.o + hit->t * ray.d;
        const Vec3 n = scene.shapes[size_t(hit->shape)].surfaceAt(hit->prim, hit->coords).ng;
        return PortalCrossing{i, p, n};
    }
    return std::nullopt;
}

PortalPerturbation::PortalPerturbation(const Scene& scene, const ReciprocalKernel& angles)
    : scene_(scene), angles_(angles) {}

bool PortalPerturbation::suitable(const MarkovPath& x) const { return portalCrossing(scene_, x.v).has_value(); }

double PortalPerturbation::density(const Vec3& from, const Vec3& n, const MarkovPath& to, size_t light) const {
    const Vec3 w = edgeDirection(to.v, light);
    const double theta = std::atan2(length(cross(from, w)), dot(from, w));
    const double cosPortal = std::abs(dot(n, w));
    if (!(cosPortal > 0)) return 0;
    return angles_.sphereDensity(theta) / cosPortal * geometryTerm(to.v[light], to.v[light + 1]);
}

void PortalPerturbation::propose(const MarkovPath& x, Pcg32& rng, Proposal& out) const {
    out = Proposal{};
    const auto crossing = portalCrossing(scene_, x.v);
    if (!crossing) {
        out.failed = RejectCause::ZeroContribution;
        return;
    }
    const size_t i = crossing->light;
    const auto& v = x.v;
    // Early rejection (Sec. 4.5): a delta vertex on the edge or next to it keeps no path nearby.
    if (isSpecular(v[i]) || isSpecular(v[i + 1]) || isSpecular(v[i + 2]) || (i > 0 && isSpecular(v[i - 1]))) {
        out.failed = RejectCause::SpecularNeighbour;
        return;
    }
    // 1. The direction about the fixed pivot (Eq. 5), in the same half as the old one (theta <= r_max < pi/2).
    const Vec3 w0 = edgeDirection(v, i);
    const double theta = angles_.sample(rng.nextDouble());
    const Vec3 w = rotateDirection(w0, theta, 2 * Pi * rng.nextDouble());
    // 2. The two vertices: the first hits from the pivot backward and forward. The light side of an edge
    // that ended on a light must reach a light again (an area emitter, or the sky when the ray leaves).
    auto eyeSide = traceVertex(scene_, Ray{crossing->p, -w});
    auto lightSide = traceOrEscape(scene_, Ray{crossing->p, w}, i == 0);
    if (!eyeSide || !lightSide) {
        out.failed = RejectCause::Missed;
        return;
    }
    if (i == 0 && !lightSide->infinite) {
        if (!lightSide->emitter || lightSide->emitter->shape < 0) {
            out.failed = RejectCause::Missed;
            return;
        }
        lightSide = lightVertexAt(scene_, size_t(lightSide->emitterIndex), lightSide->p(), lightSide->ng(),
                                  lightSide->si.prim, lightSide->si.coords);
    }
    // Both scatter through their non-delta lobes (as the half-vector mutation's moved vertices).
    for (PathVertex* moved : {&*eyeSide, &*lightSide})
        if (moved->bsdf) moved->lobe = moved->bsdf->lobes() & ~LobeDelta;
    out.y = x;
    out.y.v[i] = std::move(*lightSide);
    out.y.v[i + 1] = std::move(*eyeSide);
    // 3. The reverse move must turn the same edge about the same pivot (Sec. 4.5).
    const auto back = portalCrossing(scene_, out.y.v);
    if (!back || back->light != i || length(back->p - crossing->p) > 1e-5 * scene_.sceneRadius()) {
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

} // namespace lt
