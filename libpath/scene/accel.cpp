#include "scene/accel.h"

#include <embree3/rtcore.h>

#include <atomic>
#include <cstring>
#include <string>

#include "util/error.h"

namespace lt {

namespace {

void embreeError(void*, RTCError code, const char* str) {
    // Errors are collected by checking rtcGetDeviceError after each build step; nothing to print here
    // (libpath never prints).
    (void)code, (void)str;
}

// Per user-geometry data handed to Embree's callbacks.
struct AnalyticGeometry {
    const Shape* shape = nullptr;
    unsigned geomId = 0;
};

void analyticBounds(const RTCBoundsFunctionArguments* args) {
    const auto* g = static_cast<const AnalyticGeometry*>(args->geometryUserPtr);
    const Bounds3& b = g->shape->bounds();
    // Round outward so float bounds contain the double-precision surface.
    const double pad = 1e-6 * (b.diagonal() + 1.0);
    args->bounds_o->lower_x = std::nextafter(float(b.lo.x - pad), -1e30f);
    args->bounds_o->lower_y = std::nextafter(float(b.lo.y - pad), -1e30f);
    args->bounds_o->lower_z = std::nextafter(float(b.lo.z - pad), -1e30f);
    args->bounds_o->upper_x = std::nextafter(float(b.hi.x + pad), 1e30f);
    args->bounds_o->upper_y = std::nextafter(float(b.hi.y + pad), 1e30f);
    args->bounds_o->upper_z = std::nextafter(float(b.hi.z + pad), 1e30f);
}

double analyticHit(const AnalyticGeometry& g, const RTCRay& r) {
    return g.shape->intersectAnalytic({r.org_x, r.org_y, r.org_z}, {r.dir_x, r.dir_y, r.dir_z}, r.tnear, r.tfar);
}

void analyticIntersect(const RTCIntersectFunctionNArguments* args) {
    if (!args->valid[0]) return;
    const auto* g = static_cast<const AnalyticGeometry*>(args->geometryUserPtr);
    auto* rh = reinterpret_cast<RTCRayHit*>(args->rayhit);
    const double t = analyticHit(*g, rh->ray);
    if (t < 0) return;
    rh->ray.tfar = float(t);
    rh->hit.geomID = g->geomId;
    rh->hit.primID = args->primID;
    rh->hit.instID[0] = args->context->instID[0];
    // The exact hit is recomputed in double from the ray afterwards; u, v stay unused here.
    rh->hit.u = 0;
    rh->hit.v = 0;
    rh->hit.Ng_x = rh->hit.Ng_y = 0;
    rh->hit.Ng_z = 1;
}

void analyticOccluded(const RTCOccludedFunctionNArguments* args) {
    if (!args->valid[0]) return;
    const auto* g = static_cast<const AnalyticGeometry*>(args->geometryUserPtr);
    auto* r = reinterpret_cast<RTCRay*>(args->ray);
    if (analyticHit(*g, *r) >= 0) r->tfar = -std::numeric_limits<float>::infinity();
}

void checkDevice(RTCDevice device, const char* what) {
    const RTCError err = rtcGetDeviceError(device);
    if (err != RTC_ERROR_NONE) throw Error(std::string("Embree: ") + what + " failed (error " + std::to_string(int(err)) + ")");
}

// What Embree accepts (RayK::valid): finite origin and direction, 0 <= tnear <= tfar.
bool validRay(const Ray& ray) {
    return isFinite(ray.o) && isFinite(ray.d) && lengthSquared(ray.d) > 0 && ray.tmin >= 0 && ray.tmax >= ray.tmin;
}

RTCRay toRtc(const Ray& ray) {
    RTCRay r{};
    r.org_x = float(ray.o.x);
    r.org_y = float(ray.o.y);
    r.org_z = float(ray.o.z);
    r.dir_x = float(ray.d.x);
    r.dir_y = float(ray.d.y);
    r.dir_z = float(ray.d.z);
    r.tnear = float(ray.tmin);
    r.tfar = ray.tmax >= double(std::numeric_limits<float>::max()) ? std::numeric_limits<float>::infinity()
                                                                    : float(ray.tmax);
    r.mask = 0xFFFFFFFFu;
    r.flags = 0;
    return r;
}

std::atomic<uint64_t> globalRays{0};
thread_local uint64_t localRays = 0;

// Counting privately and publishing in batches keeps the counter off the shared cache line.
inline void countRay() {
    if (++localRays == 4096) {
        globalRays.fetch_add(localRays, std::memory_order_relaxed);
        localRays = 0;
    }
}

} // namespace

uint64_t EmbreeAccel::rayCount() { return globalRays.load(std::memory_order_relaxed); }

void EmbreeAccel::flushRayCount() {
    globalRays.fetch_add(localRays, std::memory_order_relaxed);
    localRays = 0;
}

struct EmbreeAccel::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    std::vector<int> geomToShape;
    std::vector<std::unique_ptr<AnalyticGeometry>> analytic;
    const std::vector<Shape>* shapes = nullptr;

    ~Impl() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
};

EmbreeAccel::EmbreeAccel() : impl_(std::make_unique<Impl>()) {}
EmbreeAccel::~EmbreeAccel() = default;
EmbreeAccel::EmbreeAccel(EmbreeAccel&&) noexcept = default;
EmbreeAccel& EmbreeAccel::operator=(EmbreeAccel&&) noexcept = default;

void EmbreeAccel::build(const std::vector<Shape>& shapes, const std::vector<bool>& include, bool robust) {
    impl_ = std::make_unique<Impl>();
    Impl& im = *impl_;
    im.shapes = &shapes;
    im.device = rtcNewDevice(nullptr);
    if (!im.device) throw Error("Embree: cannot create a device");
    rtcSetDeviceErrorFunction(im.device, embreeError, nullptr);
    im.scene = rtcNewScene(im.device);
    // Robust mode: watertight-ish traversal at a small speed cost; rays grazing shared edges of the
    // cornell box must not leak.
    rtcSetSceneFlags(im.scene, robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE);
    rtcSetSceneBuildQuality(im.scene, RTC_BUILD_QUALITY_HIGH);
    for (size_t i = 0; i < shapes.size(); ++i) {
        if (!include[i]) continue;
        const Shape& s = shapes[i];
        RTCGeometry geom;
        if (s.kind() == Shape::Kind::Triangles) {
            const TriangleMesh& m = s.mesh();
            geom = rtcNewGeometry(im.device, RTC_GEOMETRY_TYPE_TRIANGLE);
            // rtcSetNewGeometryBuffer pads the buffer so Embree's 16-byte loads of the last vertex are safe.
            auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                  3 * sizeof(float), m.positions.size()));
            auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                       3 * sizeof(unsigned), m.triangles.size()));
            checkDevice(im.device, "allocating a mesh");
            std::memcpy(v, m.positions.data(), m.positions.size() * sizeof(Vec3f));
            std::memcpy(idx, m.triangles.data(), m.triangles.size() * 3 * sizeof(unsigned));
        } else {
            geom = rtcNewGeometry(im.device, RTC_GEOMETRY_TYPE_USER);
            auto data = std::make_unique<AnalyticGeometry>();
            data->shape = &s;
            rtcSetGeometryUserPrimitiveCount(geom, 1);
            rtcSetGeometryUserData(geom, data.get());
            rtcSetGeometryBoundsFunction(geom, analyticBounds, nullptr);
            rtcSetGeometryIntersectFunction(geom, analyticIntersect);
            rtcSetGeometryOccludedFunction(geom, analyticOccluded);
            im.analytic.push_back(std::move(data));
        }
        rtcCommitGeometry(geom);
        const unsigned id = rtcAttachGeometry(im.scene, geom);
        rtcReleaseGeometry(geom);
        if (s.kind() != Shape::Kind::Triangles) im.analytic.back()->geomId = id;
        if (im.geomToShape.size() <= id) im.geomToShape.resize(id + 1, -1);
        im.geomToShape[id] = int(i);
    }
    rtcCommitScene(im.scene);
    checkDevice(im.device, "building the scene");
}

std::optional<RayHit> EmbreeAccel::intersect(const Ray& ray) const {
    countRay();
    if (!validRay(ray)) return std::nullopt;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh{};
    rh.ray = toRtc(ray);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(impl_->scene, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
    RayHit hit;
    hit.shape = impl_->geomToShape[rh.hit.geomID];
    hit.prim = rh.hit.primID;
    const Shape& s = (*impl_->shapes)[size_t(hit.shape)];
    if (s.kind() == Shape::Kind::Triangles) {
        hit.coords = {rh.hit.u, rh.hit.v};
        hit.t = rh.ray.tfar;
    } else {
        // Recompute the analytic hit in double from the ray as given (Embree saw it rounded to float).
        const double t = s.intersectAnalytic(ray.o, ray.d, ray.tmin, double(rh.ray.tfar) * (1 + 1e-6) + 1e-30);
        hit.t = t >= 0 ? t : rh.ray.tfar;
        const Vec3 p = ray.o + ray.d * hit.t;
        hit.coords = s.analyticCoords(p);
    }
    return hit;
}

bool EmbreeAccel::occluded(const Ray& ray) const {
    countRay();
    // A degenerate segment (its ends closer than their float offsets, or NaN) blocks: its geometry term
    // would be unbounded, and Embree asserts on invalid rays.
    if (!validRay(ray)) return true;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRay r = toRtc(ray);
    rtcOccluded1(impl_->scene, &ctx, &r);
    return r.tfar < 0;
}

} // namespace lt
