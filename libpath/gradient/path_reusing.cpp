#include "gradient/path_reusing.h"

#include <algorithm>

#include "util/error.h"
#include "math/rng.h"
#include "sampling/lens_sample.h"
#include "sampling/render.h"
#include "scene/scene.h"

namespace lt {

namespace {

enum Plane { Dx = 0, Dy = 1, Direct = 2 };

} // namespace

PathReusing::PathReusing(const Scene& scene, GradientSettings settings)
    : scene_(scene), settings_(settings), window_(cropWindow(scene.camera.film())), filter_(scene.camera.film().filter) {
    settings_.paths.check();
    if (settings_.tile < 1) throw Error("the tile size must be at least 1");
    if (!(settings_.rrDelta > 0) || !(settings_.rrMin >= 0 && settings_.rrMin <= 1))
        throw Error("Russian roulette needs delta > 0 and 0 <= q_min <= 1");
}

std::vector<Spectrum> reuseBasePaths(const Scene& scene, double shiftThreshold,
                                     const std::vector<std::optional<BaseVertex>>& primary,
                                     const std::vector<BasePath>& bases, const std::vector<double>& survival,
                                     ShiftStatistics* stats, SampleHealth& health) {
    const size_t pixels = bases.size();
    std::vector<Spectrum> value(pixels), share(pixels);
    std::vector<std::vector<EndingTerm>> shifted(pixels);
    std::vector<const std::vector<EndingTerm>*> set(pixels);
    std::vector<EndingTerm> own;
    for (size_t k = 0; k < pixels; ++k) {
        if (!(survival[k] > 0) || bases[k].vertices.empty()) continue;
        own = baseEndingTerms(scene, bases[k]);
        for (size_t m = 0; m < pixels; ++m) {
            if (m == k) {
                set[m] = &own;
                continue;
            }
            const ShiftOutcome o = shiftBasePath(scene, bases[k], primary[m], shiftThreshold, shifted[m]);
            if (stats) stats->add(o);
            set[m] = &shifted[m];
        }
        std::fill(share.begin(), share.end(), Spectrum());
        if (!shareOverPixels(set, share)) {
            ++health.nonFinite;
            continue;
        }
        for (size_t m = 0; m < pixels; ++m)
            value[m] += share[m] / survival[k];
    }
    return value;
}

Spectrum PathReusing::estimate(const Vec2&, SampleGenerator&, PixelSample&) const {
    throw Error("path reusing estimates whole tiles (estimateTile)");
}

void PathReusing::estimateTile(const TileSample& tile) const {
    const PixelRect& inner = tile.rect;
    // The traced tile: one more column and row, where the film window has them.
    const PixelRect ext{inner.x0, inner.y0, std::min(window_.x1, inner.x1 + 1), std::min(window_.y1, inner.y1 + 1)};
    const int w = ext.width();
    const size_t pixels = ext.area();
    const int filmWidth = scene_.camera.film().width;
    auto pixelIndex = [&](int x, int y) { return uint64_t(y) * uint64_t(filmWidth) + uint64_t(x); };
    const uint64_t tileKey = mixBits(pixelIndex(inner.x0, inner.y0) + 1);
    // One sub-pixel sample for the whole tile.
    IndependentSampler tileSampler = pixelSampler(tile.seed ^ 0x5bd1e9955bd1e995ULL, tile.pass, tileKey);
    const Vec2 offset = Vec2(0.5, 0.5) + filter_.sample(tileSampler.next2D());
    // And one lens point (a thin lens's; the pinhole otherwise): every shift keeps its base's.
    const PerspectiveCamera& camera = scene_.camera;
    const Vec3 lens = sampleLensPoint(camera, tileSampler);

    std::vector<std::optional<BaseVertex>> primary(pixels);
    for (size_t m = 0; m < pixels; ++m)
        primary[m] =
            primaryVertex(scene_, Vec2(ext.x0 + int(m % size_t(w)), ext.y0 + int(m / size_t(w))) + offset, lens);
    std::vector<BasePath> bases(pixels);
    std::vector<double> survival(pixels, 0.0); // 0: the base path did not survive Russian roulette
    for (size_t k = 0; k < pixels; ++k) {
        const int x = ext.x0 + int(k % size_t(w)), y = ext.y0 + int(k / size_t(w));
        // A pixel of the extra column or row is also its own tile's: a stream of this tile's, not the same path.
        IndependentSampler sampler = pixelSampler(tile.seed ^ tileKey, tile.pass, pixelIndex(x, y));
        bases[k] = traceBasePath(scene_, settings_.paths, settings_.shiftThreshold, Vec2(x, y) + offset, lens,
                                 primary[k], sampler);
        // Russian roulette on the base path by its own estimate: a black base path still lives with q_min,
        // because its shifts may carry light ([GDPR] Sec. 3.3).
        double estimate = 0;
        for (const auto& t : baseEndingTerms(scene_, bases[k]))
            if (t.density > 0) estimate += t.value.luminance() / t.density;
        const double q = std::min(1.0, std::max(settings_.rrMin, estimate / settings_.rrDelta));
        ++stats_.rrTested;
        if (sampler.next1D() < q) {
            survival[k] = q;
            ++stats_.rrSurvived;
        }
    }
    stats_.basePaths += pixels;

    const std::vector<Spectrum> value =
        reuseBasePaths(scene_, settings_.shiftThreshold, primary, bases, survival, &stats_, tile.health);
    // The inner pixels: primal, forward differences inside the traced tile, directly seen emitters.
    for (int y = inner.y0; y < inner.y1; ++y)
        for (int x = inner.x0; x < inner.x1; ++x) {
            const size_t m = size_t(y - ext.y0) * size_t(w) + size_t(x - ext.x0);
            const size_t r = size_t(y - inner.y0) * size_t(inner.width()) + size_t(x - inner.x0);
            for (int c = 0; c < 3; ++c)
                tile.result.sum[3 * r + size_t(c)] = value[m][c];
            tile.result.count[r] = 1;
            if (x + 1 < ext.x1) tile.result.planeValues.push_back({Dx, x, y, value[m + 1] - value[m]});
            if (y + 1 < ext.y1) tile.result.planeValues.push_back({Dy, x, y, value[m + size_t(w)] - value[m]});
            if (bases[m].direct.isFinite())
                tile.result.planeValues.push_back({Direct, x, y, bases[m].direct});
            else
                ++tile.health.nonFinite;
        }
}

namespace {

std::vector<OptionSpec> options() {
    std::vector<OptionSpec> o = {shiftThresholdOption()};
    for (auto& spec : pathReusingOptions())
        o.push_back(std::move(spec));
    return o;
}

} // namespace

const EstimatorKind PathReusing::Kind{
    "gdpr",
    "gradient-domain path reusing: every base path reused by all pixels of its tile",
    options(),
    gradientRecord(),
    [](const Scene& scene, const PathSettings& paths, const OptionValues& values) -> std::unique_ptr<PixelEstimator> {
        return std::make_unique<PathReusing>(scene, gradientSettings(paths, values));
    },
    [](const OptionValues& values) {
        return values.number("rr_min") == 0 ? std::string("--rr-min 0 is biased (base paths that carry nothing never "
                                                          "survive, though their shifts to other pixels would)")
                                            : std::string();
    }};

} // namespace lt
