#include "gdmlt/chain_gradient.h"

#include <climits>
#include <cmath>
#include <optional>

#include "gradient/shift_mapping.h"
#include "util/error.h"
#include "mcmc/image_contribution.h"
#include "path/path_record.h"
#include "scene/scene.h"

namespace lt {

namespace {

// The base-path vertex of surface vertex v[j] of a light-to-eye path, scattering toward v[j - 1], with density 1
// (chain_gradient.h: only the ratio of the shift's value to the base's own is used).
BaseVertex baseVertexOf(const std::vector<PathVertex>& v, size_t j, double threshold) {
    const PathVertex& pv = v[j];
    BaseVertex b;
    b.si = pv.si;
    b.bsdf = pv.bsdf;
    b.emitter = pv.emitterIndex;
    b.wi = normalize(v[j + 1].si.p - pv.si.p);
    b.connectable = connectableLobe(*pv.bsdf, pv.si.uv, false, threshold);
    b.wo = pv.directionTo(v[j - 1]);
    b.lobe = pv.delta ? Lobes(pv.lobe | LobeDelta) : Lobes(pv.lobe & ~LobeDelta);
    if (b.delta()) {
        const auto ds = b.worldBsdf().deltaEval(b.wi, b.wo, Transport::Radiance);
        if (ds) b.fCos = ds->weight * ds->pdf;
    } else {
        b.fCos = b.scatter(b.wi, b.wo).fCos;
    }
    b.pdf = 1;
    b.scattered = true;
    return b;
}

// The state as a base path with one ending (chain_gradient.h); `ending` is its index in the ending terms.
std::optional<BasePath> basePathOf(const Scene& scene, const std::vector<PathVertex>& v, const Vec2& raster,
                                   double threshold, size_t& ending) {
    const size_t n = v.size();
    BasePath base;
    base.raster = raster;
    base.rrDepth = INT_MAX;
    for (size_t j = n - 2; j >= 1; --j) {
        if (!v[j].bsdf) return std::nullopt;
        base.vertices.push_back(baseVertexOf(v, j, threshold));
    }
    BaseVertex& last = base.vertices.back();
    const size_t m = base.vertices.size();
    const PathVertex& light = v[0];
    if (light.isDeltaLight()) {
        // Point, spot and directional lights: only a light sample reaches them (deterministic for a delta light).
        if (last.delta()) return std::nullopt;
        const DirectSample ds = light.emitter->sampleDirect(last.si.p, Vec2(0.5, 0.5));
        BaseLightSample& l = last.light;
        l.emitter = light.emitterIndex;
        l.p = ds.p;
        l.n = ds.n;
        l.magnitude = ds.magnitude;
        l.wo = ds.wi;
        l.Le = ds.value;
        l.pdfLight = 1;
        l.delta = true;
        l.infinite = light.emitter->isInfinite();
        l.visible = true;
        last.scattered = false;
        ending = 2 * (m - 1);
        return base;
    }
    ending = 2 * (m - 1) + 1;
    if (light.infinite) {
        last.escaped = true;
        return base;
    }
    BaseVertex end;
    end.si = light.si;
    end.bsdf = scene.bsdfOf(end.si);
    end.emitter = light.emitterIndex;
    end.wi = -last.wo;
    base.vertices.push_back(std::move(end));
    return base;
}

double channelSum(const Spectrum& s) { return s.r + s.g + s.b; }

} // namespace

ChainShifts shiftChainState(const Scene& scene, const SensorWindow& sensor, const std::vector<PathVertex>& v,
                            const Vec2& raster, const Spectrum& f, double shiftThreshold, ShiftStatistics* stats) {
    ChainShifts out;
    for (size_t k = 0; k < 4; ++k) {
        const Vec2 r = raster + Vec2(NeighbourOffsets[k][0], NeighbourOffsets[k][1]);
        out.onFilm[k] =
            r.x >= sensor.x0 && r.x < sensor.x0 + sensor.width && r.y >= sensor.y0 && r.y < sensor.y0 + sensor.height;
    }
    size_t ending = 0;
    const auto base = basePathOf(scene, v, raster, shiftThreshold, ending);
    if (!base) return out;
    if (stats) ++stats->basePaths;
    const std::vector<EndingTerm> own = baseEndingTerms(scene, *base);
    const double ownValue = channelSum(own[ending].value);
    // f over the base's value: the measure conversion (and the camera's importance), one scalar per path.
    const double scale = ownValue > 0 ? channelSum(f) / ownValue : 0.0;
    if (!(scale > 0) || !std::isfinite(scale)) return out;
    std::vector<EndingTerm> shifted;
    for (size_t k = 0; k < 4; ++k) {
        if (!out.onFilm[k]) continue;
        const Vec2 r = raster + Vec2(NeighbourOffsets[k][0], NeighbourOffsets[k][1]);
        const ShiftOutcome o =
            shiftBasePath(scene, *base, primaryVertex(scene, r, v.back().si.p), shiftThreshold, shifted);
        if (stats) stats->add(o);
        out.F[k] = shifted[ending].value * scale;
    }
    return out;
}

PathTarget gradientTarget(const Scene& scene, double alpha, double shiftThreshold) {
    return [&scene, alpha, shiftThreshold, sensor = SensorWindow(scene.camera)](const std::vector<PathVertex>& v,
                                                                                const Vec2& raster, const Spectrum& f) {
        if (v.size() < 3) return targetValue(f);
        const ChainShifts shifts = shiftChainState(scene, sensor, v, raster, f, shiftThreshold, nullptr);
        double sum = alpha * targetValue(f);
        for (size_t k = 0; k < 4; ++k)
            if (shifts.onFilm[k]) {
                const Spectrum d = shifts.F[k] - f;
                sum += Spectrum(std::abs(d.r), std::abs(d.g), std::abs(d.b)).luminance();
            }
        return sum;
    };
}

bool addChainState(const Scene& scene, const PixelRect& window, const file::ChainState& state, double shiftThreshold,
                   ChainGradientSplats& out, ShiftStatistics* stats) {
    const Spectrum f(state.f[0], state.f[1], state.f[2]);
    const Vec2 raster(state.raster[0], state.raster[1]);
    // A chain only visits raster positions where the sensor responds: anything else (NaN included) is a damaged
    // stream, and the film's pixel lookup must never see it.
    const SensorWindow sensor(scene.camera);
    if (!(raster.x >= sensor.x0 && raster.x <= sensor.x0 + sensor.width && raster.y >= sensor.y0 &&
          raster.y <= sensor.y0 + sensor.height))
        throw Error("a chain state at raster position (" + std::to_string(raster.x) + ", " + std::to_string(raster.y) +
                    "), off the film");
    const double c = state.credit / (double(state.target) * double(window.area()));
    if (!(c > 0) || !std::isfinite(c) || !f.isFinite()) return false;
    if (state.vertices.size() == 2) {
        out.direct.push_back({raster, f * c});
        return true;
    }
    file::PathRecord record;
    record.vertices = state.vertices;
    const std::vector<PathVertex> v = verticesFromRecord(scene, record, "a chain state");
    const ChainShifts shifts = shiftChainState(scene, sensor, v, raster, f, shiftThreshold, stats);
    const double own = targetValue(f);
    const size_t first = out.primal.size(), firstDx = out.dx.size(), firstDy = out.dy.size();
    bool finite = true;
    for (size_t k = 0; k < 4; ++k) {
        if (!shifts.onFilm[k]) {
            out.primal.push_back({raster, f * (0.25 * c)});
            continue;
        }
        const Spectrum& F = shifts.F[k];
        const double w = own / (own + (F.isBlack() ? 0.0 : targetValue(F)));
        const Vec2 r = raster + Vec2(NeighbourOffsets[k][0], NeighbourOffsets[k][1]);
        out.primal.push_back({raster, f * (0.25 * w * c)});
        if (!F.isBlack()) out.primal.push_back({r, F * (0.25 * w * c)});
        // Forward differences dx(j) = I(j + x) - I(j): the pair toward +x is stored at x's pixel, the one
        // toward -x at the neighbour's (its raster position r, where h_{j-x}(r) = h_j(raster)).
        const bool forward = NeighbourOffsets[k][0] + NeighbourOffsets[k][1] > 0;
        auto& plane = NeighbourOffsets[k][0] != 0 ? out.dx : out.dy;
        plane.push_back(forward ? Splat{raster, (F - f) * (w * c)} : Splat{r, (f - F) * (w * c)});
        finite = finite && F.isFinite() && std::isfinite(w);
    }
    if (!finite) {
        out.primal.resize(first);
        out.dx.resize(firstDx);
        out.dy.resize(firstDy);
        return false;
    }
    return true;
}

} // namespace lt
