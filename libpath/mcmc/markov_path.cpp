#include "mcmc/markov_path.h"

#include "bsdf/shading_correction.h"
#include "math/error.h"
#include "path/path_record.h"

namespace lt {

namespace {

WorldBsdf worldBsdf(const PathVertex& v) { return {*v.bsdf, v.si.shading, v.si.ng, v.si.uv}; }

// The delta lobe's sample for light-to-eye importance transport at v[i] (wi toward v[i-1]).
std::optional<BsdfSample> deltaImportance(const std::vector<PathVertex>& v, size_t i) {
    return worldBsdf(v[i]).deltaEval(v[i].directionTo(v[i - 1]), v[i].directionTo(v[i + 1]), Transport::Importance);
}

// The same point with the same normal: the shadow ray between two such vertices is the same ray.
bool sameVertex(const PathVertex& a, const PathVertex& b) {
    return a.type == b.type && a.si.p == b.si.p && a.si.ng == b.si.ng;
}

// Whether `path` has an edge from a to b (light to eye). Perturbations keep most edges, the bidirectional
// mutation a prefix and a suffix (shifted when the length changes): a scan finds them either way.
bool hasEdge(const MarkovPath& path, const PathVertex& a, const PathVertex& b) {
    for (size_t j = 0; j + 1 < path.v.size(); ++j)
        if (sameVertex(path.v[j], a) && sameVertex(path.v[j + 1], b)) return true;
    return false;
}

} // namespace

std::optional<RejectCause> evaluatePath(const Scene& scene, MarkovPath& path, const MarkovPath* verified) {
    auto& v = path.v;
    path.f = {};
    path.target = 0;
    const size_t k = v.size() - 1;
    if (v.size() < 2 || v[0].type != VertexType::Light || v[k].type != VertexType::Camera)
        return RejectCause::ZeroContribution;
    // The image position and the sensor's importance, with the cosine at the pinhole: W_e cos / d^2 is
    // the camera's share of the last edge (bdpt.cpp, t = 1), the rest of G is the cosine at v[k-1].
    const PerspectiveCamera& cam = scene.camera;
    const Vec3 toPoint = v[k - 1].si.p - cam.position();
    const double dist = length(toPoint);
    const Vec3 dir = toPoint / dist;
    const auto raster = cam.rasterPosition(dir);
    if (!raster) return RejectCause::LeftImage;
    path.raster = *raster;
    const double cosCam = dot(dir, cam.forward());
    if (!(cosCam > 0) || dist * cosCam < cam.nearClip()) return RejectCause::LeftImage;

    Spectrum f = v[0].Le(scene, v[1]);
    for (size_t i = 1; i < k; ++i) {
        PathVertex& x = v[i];
        if (x.type != VertexType::Surface || !x.bsdf) return RejectCause::ZeroContribution;
        // Coincident vertices (G = 0) have no direction between them: nothing to evaluate.
        const double g = geometryTerm(v[i - 1], x);
        if (!(g > 0)) return RejectCause::ZeroContribution;
        x.wi = x.directionTo(v[i - 1]);
        f *= g;
        if (isSpecular(x)) {
            const auto d = deltaImportance(v, i);
            if (!d) return RejectCause::ConfigurationChanged;
            f *= d->weight * d->pdf; // R: the delta_perp is stripped (markov_path.h)
        } else {
            f *= x.f(v[i + 1], Transport::Importance);
        }
        if (f.isBlack()) return RejectCause::ZeroContribution;
    }
    f *= geometryTerm(v[k - 1], v[k]) * cam.importance(dir) * cosCam;
    // The pixel measurement integrates h_j (crop pixels) x f over paths (film.h): image units.
    f *= double(cam.film().cropWidth) * double(cam.film().cropHeight);
    if (f.isBlack()) return RejectCause::ZeroContribution;
    if (!f.isFinite()) return RejectCause::NonFinite;
    for (size_t i = 0; i < k; ++i)
        if (!(verified && hasEdge(*verified, v[i], v[i + 1])) && !visible(scene, v[i], v[i + 1]))
            return RejectCause::Occluded;
    path.f = f;
    path.target = targetValue(f);
    return std::nullopt;
}

MarkovPath pathFromRecord(const Scene& scene, const file::PathRecord& record, size_t index) {
    const auto fail = [&](const std::string& what) {
        return Error("seed path " + std::to_string(index) + ": " + what);
    };
    const size_t n = record.vertices.size();
    if (n < 2) throw fail("fewer than two vertices");
    MarkovPath path;
    path.v.resize(n);
    for (size_t i = 0; i < n; ++i) {
        const auto& r = record.vertices[i];
        PathVertex& x = path.v[i];
        const Vec3 p(r.p[0], r.p[1], r.p[2]);
        if (i == 0) {
            if (r.light < 0 || size_t(r.light) >= scene.emitters.size()) throw fail("its first vertex is on no light");
            if (scene.emitters[size_t(r.light)]->isInfinite())
                throw fail("starts on an environment emitter, which path-space chains do not handle yet");
            x = lightVertexAt(scene, size_t(r.light), p, Vec3(r.ng[0], r.ng[1], r.ng[2]), r.prim,
                              Vec2(r.coords[0], r.coords[1]));
            if (!x.isOnSurface() && r.shape >= 0) throw fail("its light vertex does not match the scene");
        } else if (i + 1 == n) {
            if (r.kind != file::VertexKind::Camera) throw fail("does not end on the camera");
            x.type = VertexType::Camera;
            x.si.p = scene.camera.position();
        } else {
            if (r.shape < 0 || size_t(r.shape) >= scene.shapes.size()) throw fail("names a shape the scene lacks");
            SurfaceInteraction si = scene.shapes[size_t(r.shape)].surfaceAt(r.prim, Vec2(r.coords[0], r.coords[1]));
            si.shape = r.shape;
            x = surfaceVertex(scene, si);
            // Delta scattering, except at the connection's two ends of a BDPT technique (joined through
            // the non-delta lobes): light-to-eye indices s - 1 and s. A chain's state (s = t = 0) says
            // exactly.
            const bool technique = record.s + record.t > 0;
            x.delta = (r.lobe & LobeDelta) && (!technique || (i + 1 != record.s && i != record.s));
            x.lobe = r.lobe;
        }
    }
    if (const auto why = evaluatePath(scene, path))
        throw fail(std::string("carries no light in this scene (") + rejectCauseName(*why) + ")");
    return path;
}

file::PathRecord toPathRecord(const Scene& scene, const MarkovPath& path, uint64_t chain, uint64_t mutation) {
    file::PathRecord rec;
    for (const auto& v : path.v) {
        file::VertexRecord r = toVertexRecord(scene, v);
        r.lobe = isSpecular(v) ? uint8_t(r.lobe | LobeDelta) : uint8_t(r.lobe & ~LobeDelta);
        rec.vertices.push_back(r);
    }
    rec.raster = {float(path.raster.x), float(path.raster.y)};
    rec.contribution = {float(path.f.r), float(path.f.g), float(path.f.b)};
    rec.misWeight = 1;
    rec.weight = path.target;
    rec.rngStream = chain;
    rec.rngOffset = mutation;
    return rec;
}

double densityFromLight(const Scene& scene, const std::vector<PathVertex>& v, size_t i) {
    if (i == 0) return v[0].pdfLightOrigin(scene, v[1]);
    if (i == 1) return v[0].pdfLight(scene, v[1]);
    const PathVertex& from = v[i - 1];
    if (isSpecular(from)) {
        const auto d = deltaImportance(v, i - 1);
        return d ? d->pdf * geometryTerm(from, v[i]) : 0.0;
    }
    return from.pdf(scene, &v[i - 2], v[i]);
}

double densityFromEye(const Scene& scene, const SensorWindow& sensor, const std::vector<PathVertex>& v, size_t i) {
    const size_t k = v.size() - 1;
    const PathVertex& from = v[i + 1];
    if (i + 1 == k) return from.pdf(scene, nullptr, v[i]) * sensor.cropToSensorDensity();
    if (isSpecular(from)) {
        const auto imp = deltaImportance(v, i + 1);
        const auto rad =
            worldBsdf(from).deltaEval(from.directionTo(v[i + 2]), from.directionTo(v[i]), Transport::Radiance);
        return imp && rad ? eyeSideDeltaDensity(*imp, *rad, geometryTerm(from, v[i])) : 0.0;
    }
    return from.pdf(scene, &v[i + 2], v[i]);
}

} // namespace lt
