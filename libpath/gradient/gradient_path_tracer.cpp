#include "gradient/gradient_path_tracer.h"

#include "util/error.h"
#include "sampling/lens_sample.h"
#include "scene/scene.h"

namespace lt {

namespace {

enum Plane { Dx = 0, Dy = 1, Direct = 2 };

} // namespace

GradientPathTracer::GradientPathTracer(const Scene& scene, GradientSettings settings)
    : scene_(scene), settings_(settings), window_(cropWindow(scene.camera.film())) {
    settings_.paths.check();
}

Spectrum GradientPathTracer::estimate(const Vec2& raster, SampleGenerator& sampler, PixelSample& out) const {
    const PerspectiveCamera& camera = scene_.camera;
    const Vec3 lens = sampleLensPoint(camera, sampler);
    const BasePath base = traceBasePath(scene_, settings_.paths, settings_.shiftThreshold, raster, lens,
                                        primaryVertex(scene_, raster, lens), sampler);
    ++stats_.basePaths;
    const std::vector<EndingTerm> own = baseEndingTerms(scene_, base);
    std::vector<EndingTerm> shifted;
    Spectrum primal;
    std::vector<PlaneValue> values;
    for (const auto& o : NeighbourOffsets) {
        const int nx = out.x + o[0], ny = out.y + o[1];
        std::vector<Spectrum> share(2);
        if (!window_.contains(nx, ny)) {
            if (!shareOverPixels({&own}, share)) {
                ++out.health.nonFinite;
                return {};
            }
            primal += share[0];
            continue;
        }
        stats_.add(shiftBasePath(scene_, base, primaryVertex(scene_, raster + Vec2(o[0], o[1]), lens),
                                 settings_.shiftThreshold, shifted));
        if (!shareOverPixels({&own, &shifted}, share)) {
            ++out.health.nonFinite;
            return {};
        }
        primal += share[0];
        values.push_back({PrimalPlane, o[0], o[1], share[1] * 0.25});
        // Forward differences: dx(x, y) = I(x + 1, y) - I(x, y), stored at the left or upper pixel.
        const bool forward = o[0] + o[1] > 0;
        values.push_back({o[0] != 0 ? Dx : Dy, forward ? 0 : o[0], forward ? 0 : o[1],
                          forward ? share[1] - share[0] : share[0] - share[1]});
    }
    if (!base.direct.isFinite()) {
        ++out.health.nonFinite;
        return {};
    }
    out.planes.insert(out.planes.end(), values.begin(), values.end());
    out.planes.push_back({Direct, 0, 0, base.direct});
    return primal * 0.25;
}

const EstimatorKind GradientPathTracer::Kind{
    "gpt",
    "gradient-domain path tracing: every base path shifted to its four neighbours",
    {shiftThresholdOption()},
    gradientRecord(),
    [](const Scene& scene, const PathSettings& paths, const OptionValues& values) -> std::unique_ptr<PixelEstimator> {
        return std::make_unique<GradientPathTracer>(scene, gradientSettings(paths, values));
    },
    {}};

} // namespace lt
