#include "mcmc/primary_space_target.h"

#include <climits>
#include <cmath>

namespace lt {

namespace {

PathSettings withoutRussianRoulette(PathSettings s) {
    // Multiplexed MLT fixes the subpath lengths in advance: roulette could only end a subpath early and
    // so kill the whole technique (SURVEY 4.2).
    s.rrDepth = INT_MAX;
    return s;
}

} // namespace

PrimarySpaceTarget::PrimarySpaceTarget(const Scene& scene, const PathSettings& settings, int unboundedEdges)
    : bdpt_(scene, settings), fixedLength_(scene, withoutRussianRoulette(settings)),
      minEdges_(settings.minDepth), maxEdges_(settings.maxDepth > 0 ? settings.maxDepth : unboundedEdges), sensor_(scene.camera),
      cropPixels_(double(scene.camera.film().cropWidth) * double(scene.camera.film().cropHeight)) {}

double PrimarySpaceTarget::evaluateAll(SampleGenerator& u, std::vector<ImageContribution>& out,
                                       SampleHealth& health) const {
    out.clear();
    u.startStream(SampleGenerator::CameraStream);
    const Vec2 r = sensor_.raster(u.next2D());
    thread_local std::vector<Splat> splats;
    splats.clear();
    const Spectrum L = bdpt_.sample(r, u, splats, health, nullptr);
    if (!L.isBlack()) out.push_back({r, L * sensor_.area()});
    for (const auto& s : splats)
        out.push_back({s.raster, s.value * cropPixels_});
    return out.empty() ? 0.0 : targetValue(out);
}

double PrimarySpaceTarget::evaluateMultiplexed(int edges, SampleGenerator& u, std::vector<ImageContribution>& out,
                                               SampleHealth& health) const {
    out.clear();
    if (edges < minEdges_) return 0;
    // Paths of k edges have k + 1 vertices, split as s light and t >= 1 camera vertices; lt joins the
    // single-edge paths (emitters seen directly) only with (0, 2).
    const int strategies = edges == 1 ? 1 : edges + 1;
    u.startStream(SampleGenerator::CameraStream);
    const int s = edges == 1 ? 0 : std::min(int(u.next1D() * strategies), strategies - 1);
    const int t = edges + 1 - s;
    Vec2 r = sensor_.raster(u.next2D());
    thread_local std::vector<PathVertex> camera, light;
    fixedLength_.cameraSubpath(r, u, camera, size_t(t));
    if (int(camera.size()) < t) return 0;
    if (s > 1) {
        fixedLength_.lightSubpath(u, light, size_t(s));
        if (int(light.size()) < s) return 0;
    } else {
        // s = 1 samples its light vertex anew toward the camera subpath (next-event estimation); the
        // placeholder only holds the place that vertex takes.
        light.assign(size_t(s), PathVertex{});
    }
    const Spectrum c = fixedLength_.strategy(light, camera, s, t, u, r) * double(strategies);
    if (c.isBlack()) return 0;
    if (!c.isFinite()) {
        ++health.nonFinite;
        return 0;
    }
    out.push_back({r, c * (t == 1 ? cropPixels_ : sensor_.area())});
    return targetValue(out);
}

} // namespace lt
