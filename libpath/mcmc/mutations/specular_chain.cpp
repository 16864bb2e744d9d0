#include "mcmc/mutations/specular_chain.h"

#include "bsdf/half_vector.h"
#include "bsdf/shading_correction.h"
#include "math/frame.h"
#include "math/warp.h"
#include "mcmc/mutations/trace.h"

namespace lt {

namespace {

// The probability of the delta lobe specular vertex v[i] scattered through, light to eye.
double lobeProbability(const std::vector<PathVertex>& v, size_t i) {
    const auto d = deltaImportance(v, i);
    return d ? d->pdf : 0.0;
}

} // namespace

Vec3 rotateDirection(const Vec3& dir, double theta, double phi) {
    return directionAround(dir, std::cos(theta), std::sin(theta), phi);
}

ReciprocalKernel rasterRadii(const PerspectiveCamera& camera) {
    const auto& f = camera.film();
    return {0.1, std::sqrt(0.05 * double(f.cropWidth) * double(f.cropHeight) / Pi)};
}

std::optional<BsdfSample> deltaLobe(const PathVertex& v, const Vec3& wi, Lobes kind, Transport mode) {
    if (v.type != VertexType::Surface || !v.bsdf || !v.bsdf->hasDelta()) return std::nullopt;
    // The lobe's exact direction, then deltaEval as the judge (the one place for delta lobe values).
    const WorldBsdf wb = v.worldBsdf();
    const Vec3 w = wb.shading.toLocal(wi);
    std::optional<Vec3> wo;
    if (kind == LobeReflection) {
        wo = Vec3(-w.x, -w.y, w.z);
    } else {
        // Snell through the shading normal, eta = index entered / index left (a thin dielectric reports
        // equal indices: straight through).
        const auto eta = v.bsdf->eta();
        if (!eta) return std::nullopt;
        const double e = eta->interior / eta->exterior;
        wo = refract(w, Vec3(0, 0, 1), w.z > 0 ? e : 1 / e);
    }
    if (!wo) return std::nullopt;
    auto s = wb.deltaEval(wi, wb.shading.toWorld(*wo), mode);
    if (!s || !(s->lobe & LobeDelta) || (s->lobe & (LobeReflection | LobeTransmission)) != kind) return std::nullopt;
    return s;
}

double fixedLobeDensityFromEye(const Scene& scene, const SensorWindow& sensor, const std::vector<PathVertex>& v,
                               size_t i) {
    const double p = densityFromEye(scene, sensor, v, i);
    if (!isSpecular(v[i + 1]) || !(p > 0)) return p;
    const double prob = lobeProbability(v, i + 1);
    return prob > 0 ? p / prob : 0.0;
}

double fixedLobeDensityFromLight(const Scene& scene, const std::vector<PathVertex>& v, size_t i) {
    const double p = densityFromLight(scene, v, i);
    if (i < 2 || !isSpecular(v[i - 1]) || !(p > 0)) return p;
    const double prob = lobeProbability(v, i - 1);
    return prob > 0 ? p / prob : 0.0;
}

std::optional<RejectCause> followChain(const Scene& scene, const std::vector<PathVertex>& old,
                                       std::vector<PathVertex>& v, int from, int to, const Ray& ray, double pdfDir,
                                       Transport mode, double& density) {
    const int step = to > from ? 1 : -1;
    Ray r = ray;
    std::optional<BsdfSample> last; // the delta lobe sampled at the previous vertex
    for (int i = from + step;; i += step) {
        auto hit = traceVertex(scene, r);
        if (!hit) return RejectCause::ConfigurationChanged;
        PathVertex& prev = v[size_t(i - step)];
        PathVertex& x = v[size_t(i)];
        const PathVertex& was = old[size_t(i)];
        if (!last) {
            density *= prev.convertDensity(pdfDir, *hit);
        } else {
            // Through the delta lobe at prev (markov_path.h): G from the light side; from the eye side
            // (R_imp / R_rad) G, the light-to-eye delta over the sampled one.
            double factor = geometryTerm(prev, *hit);
            if (mode == Transport::Radiance) {
                const auto imp =
                    deltaLobe(prev, normalize(hit->si.p - prev.si.p), scatterKind(prev), Transport::Importance);
                if (!imp) return RejectCause::ConfigurationChanged;
                factor = eyeSideDeltaDensity(*imp, *last, factor) / last->pdf; // the lobe was not chosen
            }
            density *= factor;
        }
        x = *hit;
        x.lobe = was.lobe;
        if (i == to) {
            x.delta = false;
            if (!x.isConnectible()) return RejectCause::ConfigurationChanged;
            return std::nullopt;
        }
        // A specular vertex of the chain: the same shape and the delta lobe of the same kind.
        x.delta = true;
        if (x.si.shape != was.si.shape) return RejectCause::ConfigurationChanged;
        last = deltaLobe(x, x.directionTo(prev), scatterKind(was), mode);
        if (!last || last->weight.isBlack()) return RejectCause::ConfigurationChanged;
        r = spawnRay(x.si.endpoint(), last->wo);
    }
}

namespace {

std::optional<Vec3> perturbLens(const PerspectiveCamera& camera, const Vec3& lens, Pcg32& rng) {
    const Vec2 u(rng.nextDouble(), rng.nextDouble());
    if (rng.nextDouble() < 0.5) return camera.sampleLens(u);
    const double R = camera.lens().apertureRadius;
    const Frame axis = Frame::fromNormal(camera.forward());
    const Vec2 step = warp::squareToUniformDiskConcentric(u) * (0.1 * R);
    const Vec3 moved = lens + axis.s * step.x + axis.t * step.y;
    if (lengthSquared(moved - camera.position()) > R * R) return std::nullopt;
    return moved;
}

} // namespace

std::optional<CameraPerturbation> perturbCamera(const PerspectiveCamera& camera, const SensorWindow& sensor,
                                                const ReciprocalKernel& radius, const Vec2& raster, const Vec3& lens,
                                                Pcg32& rng) {
    const double r = radius.sample(rng.nextDouble());
    const double phi = 2 * Pi * rng.nextDouble();
    const Vec2 moved(raster.x + r * std::cos(phi), raster.y + r * std::sin(phi));
    if (moved.x < sensor.x0 || moved.x >= sensor.x0 + sensor.width || moved.y < sensor.y0 ||
        moved.y >= sensor.y0 + sensor.height)
        return std::nullopt;
    Vec3 lensPoint = lens;
    if (camera.hasAperture()) {
        const auto p = perturbLens(camera, lens, rng);
        if (!p) return std::nullopt;
        lensPoint = *p;
    }
    CameraPerturbation c;
    c.ray = camera.generateRay(moved, lensPoint);
    c.pOffset = radius.planeDensity(r);
    // pdfEmission's pdfDir is that of a raster position uniform over the crop window: times the crop
    // window's area, the Jacobian from raster to solid angle.
    double pdfPos = 0, pdfDir = 0;
    camera.pdfEmission(lensPoint, c.ray.d, pdfPos, pdfDir);
    c.pdfDir = c.pOffset * double(camera.film().cropWidth) * double(camera.film().cropHeight) * pdfDir;
    return c;
}

double eyeChainDensity(const Scene& scene, const SensorWindow& sensor, const std::vector<PathVertex>& v, int j) {
    double p = sensor.area();
    for (int i = int(v.size()) - 2; p > 0 && i >= j; --i)
        p *= fixedLobeDensityFromEye(scene, sensor, v, size_t(i));
    return p;
}

double radiansPerPixel(const PerspectiveCamera& camera) {
    const auto& f = camera.film();
    return std::sqrt(camera.imagePlaneArea() / (double(f.cropWidth) * double(f.cropHeight)));
}

int firstNonSpecularFromEye(const std::vector<PathVertex>& v) {
    int j = int(v.size()) - 2;
    while (j > 0 && isSpecular(v[size_t(j)]))
        --j;
    return j;
}

std::optional<double> perturbLensChain(const Scene& scene, const SensorWindow& sensor, const ReciprocalKernel& radius,
                                       const MarkovPath& x, int to, Pcg32& rng, Proposal& out, double& sampled) {
    // Off the sensor window is off the image.
    const auto cam = perturbCamera(scene.camera, sensor, radius, x.raster, x.v.back().si.p, rng);
    if (!cam) {
        out.failed = RejectCause::LeftImage;
        return std::nullopt;
    }
    out.y = x;
    out.y.v.back().si.p = cam->ray.o;
    if (const auto why =
            followChain(scene, x.v, out.y.v, x.edges(), to, cam->ray, cam->pdfDir, Transport::Radiance, sampled)) {
        out.failed = why;
        return std::nullopt;
    }
    return cam->pOffset;
}

} // namespace lt
