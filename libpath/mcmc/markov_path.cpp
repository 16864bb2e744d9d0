#include "mcmc/markov_path.h"

#include <algorithm>

#include "bsdf/shading_correction.h"
#include "manifold/manifold_vertex.h"
#include "util/error.h"
#include "path/path_record.h"

namespace lt {

namespace {

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

std::optional<BsdfSample> deltaImportance(const std::vector<PathVertex>& v, size_t i) {
    return v[i].worldBsdf().deltaEval(v[i].directionTo(v[i - 1]), v[i].directionTo(v[i + 1]), Transport::Importance);
}

std::optional<RejectCause> evaluatePath(const Scene& scene, MarkovPath& path, const MarkovPath* verified) {
    auto& v = path.v;
    path.f = {};
    path.target = 0;
    const size_t k = v.size() - 1;
    if (v.size() < 2 || v[0].type != VertexType::Light || v[k].type != VertexType::Camera)
        return RejectCause::ZeroContribution;
    // The image position and the sensor's importance, with the cosine at the lens point: W_e cos / d^2 is
    // the camera's share of the last edge (bdpt.cpp, t = 1), the rest of G is the cosine at v[k-1].
    const PerspectiveCamera& cam = scene.camera;
    const Vec3& lens = v[k].si.p;
    const Vec3 dir = v[k].directionTo(v[k - 1]); // the sky seen directly: against its travel
    const auto raster = cam.rasterPosition(lens, dir);
    if (!raster) return RejectCause::LeftImage;
    path.raster = *raster;
    const double cosCam = dot(dir, cam.forward());
    if (!(cosCam > 0)) return RejectCause::LeftImage;
    if (!v[k - 1].infinite && length(v[k - 1].si.p - lens) * cosCam < cam.nearClip()) return RejectCause::LeftImage;

    // A point or spot light seen by the camera directly or through specular vertices only: every vertex is
    // fixed by the others (through a pinhole), a path space of measure zero; through a thin lens it is not,
    // but BDPT does not sample it either (no s = 1, t = 1 strategy, as pbrt-v3): both leave it out, so the
    // chains and their seeds agree (no bokeh of point lights).
    if (v[0].isDeltaLight() && std::all_of(v.begin() + 1, v.end() - 1, isSpecular))
        return RejectCause::ZeroContribution;
    // Coincident vertices (G = 0) have no direction between them: nothing to evaluate. Every edge is checked before
    // an end of it is evaluated toward the other: a BSDF handed the NaN direction of a zero-length edge read its
    // tables out of bounds (a path-space chain on kitchen-window, whose counter top lies on the counter).
    double g = geometryTerm(v[0], v[1]);
    if (!(g > 0)) return RejectCause::ZeroContribution;
    Spectrum f = v[0].Le(scene, v[1]);
    for (size_t i = 1; i < k; ++i) {
        PathVertex& x = v[i];
        if (x.type != VertexType::Surface || !x.bsdf) return RejectCause::ZeroContribution;
        x.wi = x.directionTo(v[i - 1]);
        f *= g;
        g = geometryTerm(x, v[i + 1]);
        if (!(g > 0)) return RejectCause::ZeroContribution;
        if (isSpecular(x)) {
            const auto d = deltaImportance(v, i);
            if (!d) return RejectCause::ConfigurationChanged;
            f *= d->weight * d->pdf; // R: the delta_perp is stripped (markov_path.h)
        } else {
            f *= x.f(v[i + 1], Transport::Importance);
        }
        if (f.isBlack()) return RejectCause::ZeroContribution;
    }
    f *= g * cam.importance(lens, dir) * cosCam; // g: the last edge's
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
    const std::string name = "seed path " + std::to_string(index);
    MarkovPath path;
    path.v = verticesFromRecord(scene, record, name);
    if (const auto why = evaluatePath(scene, path))
        throw Error(name + ": carries no light in this scene (" + rejectCauseName(*why) + ")");
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

void toChainState(const MarkovPath& path, uint32_t chain, double credit, file::ChainState& s) {
    s.chain = chain;
    s.credit = credit;
    s.raster = {float(path.raster.x), float(path.raster.y)};
    s.f = {float(path.f.r), float(path.f.g), float(path.f.b)};
    s.target = float(path.target);
    s.vertices.resize(path.v.size());
    for (size_t i = 0; i < path.v.size(); ++i) {
        const PathVertex& v = path.v[i];
        file::VertexRecord& r = s.vertices[i];
        r.kind = i == 0 ? file::VertexKind::Light
                        : (i + 1 == path.v.size() ? file::VertexKind::Camera : file::VertexKind::Surface);
        r.lobe = isSpecular(v) ? uint8_t(v.lobe | LobeDelta) : uint8_t(v.lobe & ~LobeDelta);
        r.shape = v.si.shape;
        r.prim = v.si.prim;
        r.coords = {v.si.coords.x, v.si.coords.y};
        if (i == 0) {
            r.light = v.emitterIndex;
            r.p = {v.si.p.x, v.si.p.y, v.si.p.z};
            r.ng = {float(v.si.ng.x), float(v.si.ng.y), float(v.si.ng.z)};
        }
    }
}

double densityFromLight(const Scene& scene, const std::vector<PathVertex>& v, size_t i) {
    // No light subpath reaches a lens (BDPT's t = 0 strategy, which lt does not use).
    if (v[i].type == VertexType::Camera) return 0;
    // A directional light's direction is a delta: choosing the emitter is all there is to it.
    if (i == 0 && v[0].infinite && v[0].isDeltaLight()) return scene.emitterSelection.pmf(size_t(v[0].emitterIndex));
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
    // The camera vertex itself: a thin lens's point, uniform on the aperture (a pinhole's never moves).
    if (i == k) return 1 / scene.camera.lensArea();
    const PathVertex& from = v[i + 1];
    if (i + 1 == k) return from.pdf(scene, nullptr, v[i]) * sensor.cropToSensorDensity();
    if (isSpecular(from)) {
        const auto imp = deltaImportance(v, i + 1);
        const auto rad =
            from.worldBsdf().deltaEval(from.directionTo(v[i + 2]), from.directionTo(v[i]), Transport::Radiance);
        return imp && rad ? eyeSideDeltaDensity(*imp, *rad, geometryTerm(from, v[i])) : 0.0;
    }
    return from.pdf(scene, &v[i + 2], v[i]);
}

void moveVertex(const Scene& scene, const ManifoldVertex& m, PathVertex& v) {
    const Lobes kind = v.lobe;
    const bool delta = v.delta;
    SurfaceInteraction si = scene.shapes[size_t(m.shape)].surfaceAt(m.prim, m.coords);
    si.shape = m.shape;
    setSurfaceVertex(scene, std::move(si), v);
    v.lobe = kind;
    v.delta = delta;
}

} // namespace lt
