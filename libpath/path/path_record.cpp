#include "path/path_record.h"

#include "util/error.h"

namespace lt {

file::VertexRecord toVertexRecord(const Scene& scene, const PathVertex& v) {
    file::VertexRecord r;
    switch (v.type) {
    case VertexType::Camera:
        r.kind = file::VertexKind::Camera;
        break;
    case VertexType::Light:
        r.kind = file::VertexKind::Light;
        break;
    case VertexType::Surface:
        r.kind = file::VertexKind::Surface;
        break;
    }
    r.lobe = v.lobe;
    // Degenerate position: the pinhole (not a thin lens) and point-like lights; degenerate direction:
    // directional light.
    if ((v.type == VertexType::Camera && !scene.camera.hasAperture()) ||
        (v.type == VertexType::Light && !v.infinite && !v.isOnSurface()))
        r.flags |= 1;
    if (v.emitter && (v.emitter->flags() & EmitterDeltaDirection)) r.flags |= 2;
    r.shape = v.si.shape;
    r.prim = v.si.prim;
    r.coords = {v.si.coords.x, v.si.coords.y};
    r.p = {v.si.p.x, v.si.p.y, v.si.p.z};
    r.ng = {float(v.si.ng.x), float(v.si.ng.y), float(v.si.ng.z)};
    const Vec3& ns = v.si.shading.n;
    r.ns = v.type == VertexType::Surface ? std::array<float, 3>{float(ns.x), float(ns.y), float(ns.z)} : r.ng;
    if (v.type == VertexType::Surface && v.si.shape >= 0) {
        r.bsdf = scene.shapes[size_t(v.si.shape)].bsdf;
        if (v.bsdf) r.roughness = float(v.bsdf->roughness(v.si.uv));
    }
    r.light = v.emitterIndex;
    r.pdfFwd = v.pdfFwd;
    r.pdfRev = v.pdfRev;
    return r;
}

double strategyWeight(const StrategyPath& path) {
    return std::max(0.0, (path.unweighted * path.misWeight).luminance());
}

namespace {

// Calls f with every vertex of a strategy's path, light to eye (the sampled vertex in place of light[0] or
// camera[0] where it replaced it).
template <class F> void forEachJoinedVertex(const StrategyPath& path, F&& f) {
    for (int i = 0; i < path.s; ++i)
        f((i == 0 && path.s == 1 && path.sampled) ? *path.sampled : (*path.light)[size_t(i)]);
    for (int i = path.t - 1; i >= 0; --i)
        f((i == 0 && path.t == 1 && path.sampled) ? *path.sampled : (*path.camera)[size_t(i)]);
}

} // namespace

std::vector<PathVertex> joinedVertices(const StrategyPath& path) {
    std::vector<PathVertex> v;
    v.reserve(size_t(path.s + path.t));
    forEachJoinedVertex(path, [&](const PathVertex& x) { v.push_back(x); });
    if (path.s > 0) v[size_t(path.s - 1)].delta = false;
    if (path.t > 0) v[size_t(path.s)].delta = false;
    return v;
}

file::PathRecord toPathRecord(const Scene& scene, const StrategyPath& path, uint64_t stream, uint64_t offset) {
    file::PathRecord rec;
    rec.vertices.reserve(size_t(path.s + path.t));
    forEachJoinedVertex(path, [&](const PathVertex& x) { rec.vertices.push_back(toVertexRecord(scene, x)); });
    rec.raster = {float(path.raster.x), float(path.raster.y)};
    rec.s = uint16_t(path.s);
    rec.t = uint16_t(path.t);
    rec.contribution = {float(path.unweighted.r), float(path.unweighted.g), float(path.unweighted.b)};
    rec.misWeight = path.misWeight;
    rec.weight = strategyWeight(path);
    rec.rngStream = stream;
    rec.rngOffset = offset;
    return rec;
}

std::vector<PathVertex> verticesFromRecord(const Scene& scene, const file::PathRecord& record,
                                           const std::string& name) {
    const auto fail = [&](const std::string& what) { return Error(name + ": " + what); };
    const size_t n = record.vertices.size();
    if (n < 2) throw fail("fewer than two vertices");
    std::vector<PathVertex> v(n);
    for (size_t i = 0; i < n; ++i) {
        const auto& r = record.vertices[i];
        PathVertex& x = v[i];
        const Vec3 p(r.p[0], r.p[1], r.p[2]);
        if (i == 0) {
            if (r.light < 0 || size_t(r.light) >= scene.emitters.size()) throw fail("its first vertex is on no light");
            const Emitter& e = *scene.emitters[size_t(r.light)];
            if (e.shape >= 0 && r.prim >= scene.shapes[size_t(e.shape)].primitiveCount())
                throw fail("its light vertex names a primitive the emitter's shape lacks");
            // An infinite emitter's vertex holds its travel direction, stored in float: made unit again.
            const Vec3 n(r.ng[0], r.ng[1], r.ng[2]);
            x = lightVertexAt(scene, size_t(r.light), p, e.isInfinite() ? normalize(n) : n, r.prim,
                              Vec2(r.coords[0], r.coords[1]));
            if (!x.isOnSurface() && r.shape >= 0) throw fail("its light vertex does not match the scene");
        } else if (i + 1 == n) {
            if (r.kind != file::VertexKind::Camera) throw fail("does not end on the camera");
            x.type = VertexType::Camera;
            x.si.p = scene.camera.position();
            // A thin lens's vertex is where on the aperture the path passed.
            if (scene.camera.hasAperture()) {
                if (!scene.camera.onLens(p)) throw fail("its camera vertex is not on the scene's lens");
                x.si.p = p;
            }
        } else {
            if (r.shape < 0 || size_t(r.shape) >= scene.shapes.size()) throw fail("names a shape the scene lacks");
            const Shape& shape = scene.shapes[size_t(r.shape)];
            if (r.prim >= shape.primitiveCount()) throw fail("names a primitive its shape lacks");
            SurfaceInteraction si = shape.surfaceAt(r.prim, Vec2(r.coords[0], r.coords[1]));
            si.shape = r.shape;
            x = surfaceVertex(scene, si);
            const bool technique = record.s + record.t > 0;
            x.delta = (r.lobe & LobeDelta) && (!technique || (i + 1 != record.s && i != record.s));
            x.lobe = r.lobe;
        }
    }
    return v;
}

} // namespace lt
