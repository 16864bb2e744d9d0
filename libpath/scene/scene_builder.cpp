// SceneObject tree -> Scene: shapes (with their meshes loaded and transformed), emitters, the sensor
// and the rendering defaults. BSDFs and textures are built by PluginFactory.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>

#include "math/constants.h"
#include "util/error.h"
#include "util/number_text.h"
#include "bsdf/bump_mapped.h"
#include "scene/emitters/sun_position.h"
#include "scene/emitters/sun_sky.h"
#include "scene/missing_file.h"
#include "scene/plugin_factory.h"
#include "scene/scene.h"

namespace lt {

namespace {

namespace fs = std::filesystem;

// FNV-1a, 64 bit: a content hash that needs no dependency. It identifies a scene's files; it is not a
// defence against deliberate collisions.
void hashBytes(uint64_t& h, const char* data, size_t n) {
    for (size_t i = 0; i < n; ++i) {
        h ^= uint64_t(static_cast<unsigned char>(data[i]));
        h *= 1099511628211ULL;
    }
}

void hashFile(uint64_t& h, const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    char buf[1 << 16];
    while (in) {
        in.read(buf, sizeof buf);
        hashBytes(h, buf, size_t(in.gcount()));
    }
}

// The diagonal field of view, in degrees, of a lens of focal length `mm` on 35 mm film (36 x 24 mm), as
// Mitsuba converts `focalLength` (0.6 src/librender/sensor.cpp; the same in 3).
double fullFrameFov(double mm) { return 2 * std::atan(std::sqrt(36.0 * 36.0 + 24.0 * 24.0) / (2 * mm)) * 180 / Pi; }

// A perspective sensor without `fov`: its `focalLength` ("50mm" by default, the unit optional) as a field of view.
double focalLengthFov(const SceneObject& o) {
    std::string text = o.has("focalLength") && o.props.at("focalLength").type != Property::Type::String
                           ? std::to_string(o.getFloat("focalLength"))
                           : o.getString("focalLength", "50mm");
    if (text.size() > 2 && text.compare(text.size() - 2, 2, "mm") == 0) text.resize(text.size() - 2);
    const double mm = numberFromText(text).value_or(0);
    if (!(mm > 0) || !std::isfinite(mm))
        o.fail("focalLength must be a positive length in millimetres such as \"50mm\", not '" + text + "'");
    return fullFrameFov(mm);
}

class Builder {
public:
    Builder(Scene& scene, const XmlDocument& doc, UnknownProperties unknown)
        : scene_(scene), doc_(doc), unread_(unknown == UnknownProperties::Fail),
          factory_([this](const SceneObject& o, const std::string& f) { return resolve(o, f); }, unread_) {}

    void build() {
        scene_.contentHash = 1469598103934665603ULL;
        for (const auto& f : doc_.filesRead) hashFile(scene_.contentHash, f);
        std::vector<std::pair<const SceneObject*, int>> areaEmitters;   // (emitter, shape index)
        bool haveSensor = false;
        for (const auto& c : doc_.root->children) {
            if (c->tag == "shape" && c->type == "shapegroup") {
                checkShapeGroup(*c);
            } else if (c->tag == "shape" && c->type == "instance") {
                buildInstance(*c, areaEmitters);
            } else if (c->tag == "shape") {
                buildShape(*c, areaEmitters);
            } else if (c->tag == "bsdf") {
                (void)bsdfIndex(*c);
            } else if (c->tag == "texture") {
                (void)factory_.texture(*c);
            } else if (c->tag == "emitter") {
                if (c->type == "area") c->fail("an area emitter must be nested inside a <shape>");
                buildEmitter(*c);
            } else if (c->tag == "sensor") {
                if (haveSensor) c->fail("the scene has more than one sensor; lt renders one");
                buildSensor(*c);
                haveSensor = true;
            } else if (c->tag == "integrator") {
                buildIntegrator(*c);
            } else {
                c->fail("must be nested inside a <sensor> (film, rfilter, sampler) or is not allowed at scene level");
            }
        }
        // Area emitters are made once the shape list is final: they keep references to their shapes.
        for (const auto& [e, shapeIndex] : areaEmitters) {
            auto emitter = makeAreaEmitter(scene_.shapes[size_t(shapeIndex)], shapeIndex,
                                           e->getSpectrum("radiance", Spectrum(1.0)));
            emitter->origin = e->file + ':' + std::to_string(e->line);
            finish(*e, {"samplingWeight"});
            scene_.shapes[size_t(shapeIndex)].emitter = int(scene_.emitters.size());
            scene_.emitters.push_back(std::move(emitter));
        }
        if (!haveSensor) scene_.camera = defaultCamera();
        scene_.ignoredHints = unread_.hints();
        for (const auto& w : unread_.warnings())
            scene_.warnings.push_back(w);
        for (const auto& w : factory_.warnings)
            scene_.warnings.push_back(w);
        scene_.finalize();
    }

private:
    Scene& scene_;
    const XmlDocument& doc_;
    UnreadProperties unread_;
    PluginFactory factory_;
    std::map<const SceneObject*, int> bsdfIndices_; // by declaration (SceneObject::declaration())
    std::map<const SceneObject*, TriangleMesh> instancedMeshes_; // untransformed, by declaration

    std::string resolve(const SceneObject& o, const std::string& filename) {
        fs::path p = filename;
        if (p.is_relative()) {
            // Relative to the file that names it, then to the main scene's directory (Mitsuba's
            // file resolver searches the scene's directory).
            const fs::path local = fs::path(o.file).parent_path() / p;
            const fs::path main = fs::path(scene_.filename).parent_path() / p;
            p = fs::exists(local) || !fs::exists(main) ? local : main;
        }
        if (!fs::exists(p)) o.fail("file not found: " + p.string() + didYouMean(p));
        hashFile(scene_.contentHash, p.string());
        return p.string();
    }

    void finish(const SceneObject& o, const std::set<std::string>& hints = {}) { unread_.check(o, hints); }

    int bsdfIndex(const SceneObject& o) {
        auto it = bsdfIndices_.find(o.declaration());
        if (it != bsdfIndices_.end()) return it->second;
        const int index = int(scene_.bsdfs.size());
        scene_.bsdfs.push_back({factory_.bsdf(o), o.id, o.file + ':' + std::to_string(o.line)});
        bsdfIndices_[o.declaration()] = index;
        return index;
    }

    // Mitsuba 0.6's camera for a scene without a sensor (src/librender/scene.cpp, Scene::configure):
    // fov 45 along x, looking along +z from in front of the shapes' bounding box, far enough back to see
    // its extent in x and y, near clip a hundredth of that distance; 768 x 576 film.
    PerspectiveCamera defaultCamera() const {
        Bounds3 box;
        for (const auto& shape : scene_.shapes)
            if (!shape.portal) box.expand(shape.bounds());
        Film film;
        if (!box.valid()) return PerspectiveCamera(Transform(), 45.0, FovAxis::X, film, 1e-2);
        const Vec3 extent = box.hi - box.lo, center = (box.lo + box.hi) * 0.5;
        const double distance = std::max(extent.x, extent.y) / (2 * std::tan(degToRad(45.0 / 2)));
        return PerspectiveCamera(Transform::translate({center.x, center.y, box.lo.z - distance}), 45.0, FovAxis::X,
                                 film, distance > 0 ? distance / 100 : 1e-2);
    }

    // Mitsuba's `shapegroup`: shapes placed only through `instance`s (it renders nothing itself).
    void checkShapeGroup(const SceneObject& o) {
        static const std::set<std::string> ShapeTypes = {"obj",  "ply",    "serialized", "rectangle",
                                                         "cube", "sphere", "disk"};
        for (const auto& c : o.children) {
            if (c->tag != "shape") c->fail("a shapegroup holds shapes only");
            if (c->type == "shapegroup" || c->type == "instance") c->fail("shapegroups do not nest");
            if (!ShapeTypes.count(c->type))
                c->fail("unknown shape type (lt reads obj, ply, serialized, rectangle, cube, sphere, disk)");
            if (!c->childrenWithTag("emitter").empty()) c->fail("a shape in a shapegroup cannot emit (as in Mitsuba)");
        }
        finish(o);
    }

    // Mitsuba's `instance`: its shapegroup's shapes, each placed by the instance's toWorld after its own.
    // The shapes are copied into the scene (flattened), so every method sees ordinary geometry; memory
    // grows with the number of instances.
    void buildInstance(const SceneObject& o, std::vector<std::pair<const SceneObject*, int>>& areaEmitters) {
        const SceneObject* group = nullptr;
        for (const auto& c : o.children) {
            if (c->tag != "shape" || c->type != "shapegroup") c->fail("an instance takes one <ref> to a shapegroup");
            if (group) c->fail("an instance takes one shapegroup");
            group = c.get();
        }
        if (!group) o.fail("an instance needs a <ref> to a shapegroup");
        checkShapeGroup(*group); // again for a group written inside the instance (checks count once)
        const Transform toWorld = o.getTransform("toWorld", Transform());
        for (const auto& shape : group->children)
            buildShape(*shape, areaEmitters, &toWorld);
        finish(o);
    }

    // `placement`, for a shape of an instanced shapegroup, puts the shape's own toWorld into the scene.
    void buildShape(const SceneObject& o, std::vector<std::pair<const SceneObject*, int>>& areaEmitters,
                    const Transform* placement = nullptr) {
        const Transform toWorld = (placement ? *placement : Transform()) * o.getTransform("toWorld", Transform());
        const bool flip = o.getBoolean("flipNormals", false);
        Shape shape;
        MeshLoadReport report;
        auto loadMesh = [&](TriangleMesh mesh, bool loaderFlippedV) {
            // Texture coordinates as Mitsuba reads each format: obj flips v (flipTexCoords, default true;
            // loadObj already flips), ply uses them as stored and reads flipTexCoords (default false) only in
            // Mitsuba 3.4 and later (a 0.6 scene's flipTexCoords on a ply is unread, as in Mitsuba 0.6);
            // serialized meshes and the built-in shapes have no such option.
            const bool hasFlipOption = o.type == "obj" || (o.type == "ply" && o.syntax == SceneSyntax::Mitsuba3);
            if (hasFlipOption && o.getBoolean("flipTexCoords", loaderFlippedV) != loaderFlippedV)
                for (auto& uv : mesh.uvs)
                    uv.y = 1.0f - uv.y;
            if (o.getBoolean("faceNormals", false)) mesh.normals.clear();
            transformMesh(mesh, toWorld);
            return Shape::triangles(std::move(mesh), flip);
        };
        // A mesh file is read once per declaration: the instances of a shapegroup reuse it (and report its
        // repairs once).
        auto fileMesh = [&](const std::function<TriangleMesh()>& read) {
            if (!placement) return read();
            auto it = instancedMeshes_.find(o.declaration());
            if (it == instancedMeshes_.end()) it = instancedMeshes_.emplace(o.declaration(), read()).first;
            return it->second;
        };
        try {
            if (o.type == "obj") {
                shape = loadMesh(fileMesh([&] { return loadObj(resolve(o, o.getString("filename")), report); }), true);
            } else if (o.type == "ply") {
                shape = loadMesh(fileMesh([&] { return loadPly(resolve(o, o.getString("filename")), report); }), false);
            } else if (o.type == "serialized") {
                shape = loadMesh(fileMesh([&] {
                                     return loadSerialized(resolve(o, o.getString("filename")),
                                                           o.getInteger("shapeIndex", 0), report);
                                 }),
                                 false);
            } else if (o.type == "rectangle") {
                shape = loadMesh(makeRectangleMesh(), false);
            } else if (o.type == "cube") {
                shape = loadMesh(makeCubeMesh(), false);
            } else if (o.type == "sphere") {
                const Vec3 c = toWorld.point(o.getPoint("center", Vec3(0, 0, 0)));
                // Mitsuba allows a toWorld with uniform scale on spheres: the radius scales with it.
                const Vec3 ex = toWorld.vector({1, 0, 0}), ey = toWorld.vector({0, 1, 0}), ez = toWorld.vector({0, 0, 1});
                const double sx = length(ex), sy = length(ey), sz = length(ez);
                if (std::abs(sx - sy) > 1e-6 * sx || std::abs(sx - sz) > 1e-6 * sx)
                    o.fail("a sphere's toWorld must scale uniformly (use a mesh for ellipsoids)");
                shape = Shape::sphere(c, o.getFloat("radius", 1.0) * sx, flip);
            } else if (o.type == "disk") {
                shape = Shape::disk(toWorld, flip);
            } else {
                o.fail("unknown shape type (lt reads obj, ply, serialized, rectangle, cube, sphere, disk, shapegroup, "
                       "instance)");
            }
        } catch (const Error& e) {
            const std::string what = e.what();
            // Loader messages start with the mesh file; put the XML element in front.
            if (what.find(o.file + ':') == 0) throw;
            o.fail(what);
        }
        if (report.degenerateTrianglesRemoved > 0)
            scene_.warnings.push_back(o.where() + ": removed " + std::to_string(report.degenerateTrianglesRemoved) +
                                      " degenerate triangle(s)");
        shape.portal = o.getBoolean("portal", false);
        shape.type = o.type;
        shape.id = o.id;
        shape.origin = o.file + ':' + std::to_string(o.line);
        const SceneObject* emitter = nullptr;
        for (const auto& c : o.children) {
            if (c->tag == "bsdf") {
                if (shape.bsdf >= 0) c->fail("a shape takes one BSDF");
                shape.bsdf = bsdfIndex(*c);
            } else if (c->tag == "emitter") {
                if (c->type != "area") c->fail("only area emitters can be attached to a shape");
                if (emitter) c->fail("a shape takes one emitter");
                emitter = c.get();
            } else {
                c->fail("not allowed inside a <shape>");
            }
        }
        if (shape.portal && emitter) o.fail("a portal cannot emit light");
        if (shape.bsdf < 0 && !shape.portal) {
            shape.bsdf = int(scene_.bsdfs.size());
            scene_.bsdfs.push_back({PluginFactory::defaultBsdf(), "", shape.origin});
        }
        // A bumpmap tilts the shading frame of the shape's points (scene/bump_frame.h).
        if (shape.bsdf >= 0)
            if (const auto* bumped = dynamic_cast<const BumpMappedBsdf*>(scene_.bsdfs[size_t(shape.bsdf)].bsdf.get()))
                shape.bump = bumped->displacement();
        finish(o, {"maxSmoothAngle"});
        if (emitter) areaEmitters.emplace_back(emitter, int(scene_.shapes.size()));
        scene_.shapes.push_back(std::move(shape));
    }

    // Mitsuba 0.6's sky, sun and sunsky (sunmodel.h computeSunCoordinates, sky.cpp, sun.cpp, sunsky.cpp).
    std::vector<std::unique_ptr<Emitter>> buildDaylight(const SceneObject& o) {
        const bool sky = o.type != "sun", sun = o.type != "sky";
        DaylightSettings d;
        d.toWorld = o.getTransform("toWorld", Transform());
        if (o.has("sunDirection")) {
            for (const char* k : {"latitude", "longitude", "timezone", "day", "time"})
                if (o.has(k))
                    o.fail(std::string("give the sun either by sunDirection or by time and place, not both (") + k +
                           " with sunDirection)");
            const Vec3 local = d.toWorld.inverse().vector(o.getVector("sunDirection"));
            if (!(length(local) > 0)) o.fail("sunDirection must be non-zero");
            d.sun = skyAngles(normalize(local));
        } else {
            SunLocation place;
            place.latitude = o.getFloat("latitude", place.latitude);
            place.longitude = o.getFloat("longitude", place.longitude);
            place.timezone = o.getFloat("timezone", place.timezone);
            SunTime time;
            time.year = o.getInteger("year", time.year);
            time.month = o.getInteger("month", time.month);
            time.day = o.getInteger("day", time.day);
            time.hour = o.getFloat("hour", time.hour);
            time.minute = o.getFloat("minute", time.minute);
            time.second = o.getFloat("second", time.second);
            if (time.month < 1 || time.month > 12 || time.day < 1 || time.day > 31)
                o.fail("month must be in [1, 12] and day in [1, 31]");
            d.sun = sunPosition(time, place);
            if (!std::isfinite(d.sun.zenith) || !std::isfinite(d.sun.azimuth))
                o.fail("the time and place give no sun position (a number is not finite)");
        }
        d.turbidity = o.getFloat("turbidity", d.turbidity);
        d.stretch = o.getFloat("stretch", d.stretch);
        d.resolution = o.getInteger("resolution", d.resolution);
        const double scale = o.getFloat("scale", 1.0);
        if (sky) {
            d.albedo = o.getSpectrum("albedo", d.albedo);
            d.extend = o.getBoolean("extend", d.extend);
            d.skyScale = sun ? o.getFloat("skyScale", scale) : scale;
        }
        if (sun) {
            d.sunScale = sky ? o.getFloat("sunScale", scale) : scale;
            d.sunRadiusScale = o.getFloat("sunRadiusScale", d.sunRadiusScale);
        }
        return makeDaylightEmitters(d, sky, sun, o.type);
    }

    void buildEmitter(const SceneObject& o) {
        std::unique_ptr<Emitter> e;
        std::vector<std::unique_ptr<Emitter>> daylight;
        try {
            if (o.type == "point") {
                const Vec3 pos = o.has("position") ? o.getPoint("position")
                                                   : o.getTransform("toWorld", Transform()).point({0, 0, 0});
                e = makePointEmitter(pos, o.getSpectrum("intensity", Spectrum(1.0)));
            } else if (o.type == "spot") {
                const double cutoff = o.getFloat("cutoffAngle", 20.0);
                e = makeSpotEmitter(o.getTransform("toWorld", Transform()), o.getSpectrum("intensity", Spectrum(1.0)),
                                    cutoff, o.getFloat("beamWidth", cutoff * 3.0 / 4.0));
            } else if (o.type == "directional") {
                Vec3 dir = o.has("direction") ? o.getVector("direction")
                                              : o.getTransform("toWorld", Transform()).vector({0, 0, 1});
                if (!(length(dir) > 0)) o.fail("direction must be non-zero");
                e = makeDirectionalEmitter(normalize(dir), o.getSpectrum("irradiance", Spectrum(1.0)));
            } else if (o.type == "constant") {
                e = makeConstantEmitter(o.getSpectrum("radiance", Spectrum(1.0)));
            } else if (o.type == "envmap") {
                e = makeEnvmapEmitter(resolve(o, o.getString("filename")), o.getTransform("toWorld", Transform()),
                                      o.getFloat("scale", 1.0));
            } else if (o.type == "sky" || o.type == "sun" || o.type == "sunsky") {
                daylight = buildDaylight(o);
            } else {
                o.fail("unknown emitter type (lt reads area, point, spot, directional, constant, envmap, sky, sun, "
                       "sunsky)");
            }
        } catch (const Error& err) {
            const std::string what = err.what();
            if (what.find(o.file + ':') == 0) throw;
            o.fail(what);
        }
        if (e) daylight.push_back(std::move(e));
        for (auto& emitter : daylight) {
            emitter->origin = o.file + ':' + std::to_string(o.line);
            scene_.emitters.push_back(std::move(emitter));
        }
        finish(o, {"samplingWeight", "gamma", "cache"});
    }

    void buildSensor(const SceneObject& o) {
        if (o.type != "perspective" && o.type != "thinlens")
            o.fail("unsupported sensor type (lt reads perspective and thinlens)");
        Film film;
        bool haveFilm = false;
        for (const auto& c : o.children) {
            if (c->tag == "film") {
                film = buildFilm(*c);
                haveFilm = true;
            } else if (c->tag == "sampler") {
                scene_.integrator.sampleCount = c->getInteger("sampleCount", 4);
                if (scene_.integrator.sampleCount < 1) c->fail("sampleCount must be at least 1");
                finish(*c, {"scramble", "dimension", "resolution"});
                if (c->type != "independent")
                    unread_.addHint("sampler " + c->type + ": type (lt uses its own sample generator)");
            } else {
                c->fail("not allowed inside a <sensor>");
            }
        }
        (void)haveFilm;
        if (o.has("fov") && o.has("focalLength")) o.fail("give fov or focalLength, not both");
        // Without fov, Mitsuba takes the focal length's diagonal field of view (fovAxis then unread).
        const double fov = o.has("fov") ? o.getFloat("fov") : focalLengthFov(o);
        // Mitsuba reads fovAxis either way (so never warns about it) and uses it only with fov.
        const std::string givenAxis = o.getString("fovAxis", "x");
        const std::string axisName = o.has("fov") ? givenAxis : "diagonal";
        FovAxis axis;
        if (axisName == "x") axis = FovAxis::X;
        else if (axisName == "y") axis = FovAxis::Y;
        else if (axisName == "diagonal") axis = FovAxis::Diagonal;
        else if (axisName == "smaller") axis = FovAxis::Smaller;
        else if (axisName == "larger") axis = FovAxis::Larger;
        else o.fail("fovAxis must be x, y, diagonal, smaller or larger, not '" + axisName + "'");
        const double nearClip = o.getFloat("nearClip", 1e-2);
        // Mitsuba's thinlens: apertureRadius required (Mitsuba turns 0 into a tiny aperture; lt into the
        // pinhole it amounts to), focusDistance by default farClip (1e4).
        ThinLens lens;
        if (o.type == "thinlens") {
            if (!o.has("apertureRadius")) o.fail("a thinlens sensor needs apertureRadius");
            lens.apertureRadius = o.getFloat("apertureRadius");
            lens.focusDistance = o.getFloat("focusDistance", o.getFloat("farClip", 1e4));
        }
        try {
            scene_.camera = PerspectiveCamera(o.getTransform("toWorld", Transform()), fov, axis, film, nearClip, lens);
        } catch (const Error& e) {
            o.fail(e.what());
        }
        // Mitsuba's projective cameras all read focusDistance (0.6 sensor.cpp, 3's ProjectiveCamera); a
        // pinhole has no use for it.
        finish(o, {"farClip", "shutterOpen", "shutterClose", "focusDistance"});
    }

    Film buildFilm(const SceneObject& o) {
        if (o.type != "hdrfilm" && o.type != "ldrfilm" && o.type != "mfilm")
            o.fail("unsupported film type (lt writes linear EXR from hdrfilm or ldrfilm)");
        Film film;
        film.type = o.type;
        film.width = o.getInteger("width", 768);
        film.height = o.getInteger("height", 576);
        if (film.width < 1 || film.height < 1) o.fail("width and height must be at least 1");
        film.cropX = o.getInteger("cropOffsetX", 0);
        film.cropY = o.getInteger("cropOffsetY", 0);
        film.cropWidth = o.getInteger("cropWidth", film.width - film.cropX);
        film.cropHeight = o.getInteger("cropHeight", film.height - film.cropY);
        if (film.cropX < 0 || film.cropY < 0 || film.cropWidth < 1 || film.cropHeight < 1 ||
            film.cropX + film.cropWidth > film.width || film.cropY + film.cropHeight > film.height)
            o.fail("the crop window must lie inside the film");
        for (const auto& c : o.children) {
            if (c->tag != "rfilter") c->fail("not allowed inside a <film>");
            if (c->type == "box") {
                film.filter = {PixelFilter::Type::Box, c->getFloat("radius", 0.5), 0.5};
            } else if (c->type == "tent") {
                // Mitsuba 0.5's tent has a fixed radius of one pixel; a given radius is a hint it ignores.
                film.filter = {PixelFilter::Type::Tent, 1.0, 0.5};
            } else if (c->type == "gaussian") {
                const double sd = c->getFloat("stddev", 0.5);
                film.filter = {PixelFilter::Type::Gaussian, 4 * sd, sd};
            } else {
                c->fail("unsupported reconstruction filter (lt has box, tent, gaussian)");
            }
            if (!(film.filter.radius > 0)) c->fail("filter radius must be positive");
            finish(*c, c->type == "tent" ? std::set<std::string>{"radius"} : std::set<std::string>{});
        }
        // ldrfilm is a hint: lt always writes linear EXR (the shared scenes' README says so).
        finish(o, {"banner", "gamma", "pixelFormat", "fileFormat", "componentFormat", "attachLog", "highQualityEdges",
                   "tonemapMethod", "exposure", "key", "burn"});
        return film;
    }

    void buildIntegrator(const SceneObject& o) {
        scene_.integrator.type = o.type;
        // Mitsuba's `direct` renders the emitters seen directly and single scattering: paths of two edges.
        scene_.integrator.maxDepth = o.getInteger("maxDepth", o.type == "direct" ? 2 : -1);
        scene_.integrator.rrDepth = o.getInteger("rrDepth", 5);
        if (scene_.integrator.maxDepth < -1 || scene_.integrator.maxDepth == 0)
            o.fail("maxDepth must be -1 (unbounded) or at least 1");
        if (scene_.integrator.rrDepth < 1) o.fail("rrDepth must be at least 1");
        // Every other integrator option is the renderer's business: lt's tools take their own.
        std::set<std::string> hints;
        for (const auto& [key, p] : o.props)
            if (!p.queried) hints.insert(key);
        finish(o, hints);
        for (const auto& c : o.children)
            if (c->tag != "integrator") c->fail("not allowed inside an <integrator>");
    }
};

} // namespace

std::unique_ptr<Scene> loadScene(const std::string& filename, const std::map<std::string, std::string>& parameters,
                                 UnknownProperties unknown) {
    auto scene = std::make_unique<Scene>();
    scene->filename = filename;
    const XmlDocument doc = parseSceneXml(filename, parameters);
    Builder(*scene, doc, unknown).build();
    return scene;
}

} // namespace lt
