#include "image/film.h"

#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "util/memory_budget.h"

namespace lt {

SampleFilm::SampleFilm(const PerspectiveCamera& camera, std::vector<std::string> planes)
    : window_(cropWindow(camera.film())), filter_(camera.film().filter), planeNames_(std::move(planes)) {
    // Sums and splats in double, the pass statistics, the sample counts, and the developed float image a
    // tool writes. Checked for both sums, though a film allocates the one it uses only (allocated()): a
    // film that runs out of memory says so now, not at its first splat.
    const size_t passPlanes = planeNames_.empty() ? 0 : 1 + planeNames_.size();
    const double bytesPerPixel = double(3 * (2 + planeNames_.size()) + 2 * passPlanes) * sizeof(double) +
                                 sizeof(uint32_t) + double(3 * (1 + planeNames_.size()) + passPlanes) * sizeof(float);
    requireMemory(bytesPerPixel * double(window_.area()),
                  "a film of " + std::to_string(window_.width()) + "x" + std::to_string(window_.height()) + " pixels");
    planeSums_.assign(planeNames_.size(), std::vector<double>(window_.area() * 3, 0.0));
    count_.assign(window_.area(), 0);
    passStart_.assign(passPlanes, std::vector<double>(window_.area(), 0.0));
    passSquares_.assign(passPlanes, std::vector<double>(window_.area(), 0.0));
}

std::pair<int, int> SampleFilm::rowsAround(const Vec2& raster) const {
    // Pixels whose filter support contains the position: centers within the radius of it.
    const double r = filter_.radius();
    return {std::max(window_.y0, int(std::ceil(raster.y - r - 0.5))),
            std::min(window_.y1 - 1, int(std::floor(raster.y + r - 0.5)))};
}

template <class F> void SampleFilm::forEachPixel(const Vec2& raster, F&& f, int rowLo, int rowHi) const {
    const double r = filter_.radius();
    const int xa = std::max(window_.x0, int(std::ceil(raster.x - r - 0.5)));
    const int xb = std::min(window_.x1 - 1, int(std::floor(raster.x + r - 0.5)));
    auto [ya, yb] = rowsAround(raster);
    ya = std::max(ya, rowLo);
    yb = std::min(yb, rowHi - 1);
    for (int y = ya; y <= yb; ++y)
        for (int x = xa; x <= xb; ++x) {
            const double w = filter_.eval({raster.x - (x + 0.5), raster.y - (y + 0.5)});
            if (w != 0) f(size_t(y - window_.y0) * size_t(width()) + size_t(x - window_.x0), w);
        }
}

double SampleFilm::filterSum(const Vec2& raster) const {
    double sum = 0;
    forEachPixel(raster, [&](size_t, double w) { sum += w; });
    return sum;
}

std::vector<double>& SampleFilm::allocated(std::vector<double>& sums) {
    if (sums.empty()) sums.assign(window_.area() * 3, 0.0);
    return sums;
}

void SampleFilm::merge(const TileResult& tile) {
    if (!tile.sum.empty()) allocated(sum_);
    for (int y = tile.rect.y0; y < tile.rect.y1; ++y)
        for (int x = tile.rect.x0; x < tile.rect.x1; ++x) {
            const size_t src = size_t(y - tile.rect.y0) * size_t(tile.rect.width()) + size_t(x - tile.rect.x0);
            const size_t dst = size_t(y - window_.y0) * size_t(width()) + size_t(x - window_.x0);
            for (int c = 0; c < 3; ++c)
                sum_[3 * dst + size_t(c)] += tile.sum[3 * src + size_t(c)];
            count_[dst] += tile.count[src];
            cameraSamples_ += tile.count[src];
        }
    if (!tile.splats.empty()) allocated(splat_);
    for (const auto& s : tile.splats)
        addSplat(s, window_.y0, window_.y1);
    for (const auto& v : tile.planeValues) {
        if (v.plane < -1 || v.plane >= int(planeSums_.size()) || v.x < window_.x0 || v.x >= window_.x1 ||
            v.y < window_.y0 || v.y >= window_.y1)
            continue; // off the stored window (a neighbour beyond the crop)
        const size_t dst = size_t(v.y - window_.y0) * size_t(width()) + size_t(v.x - window_.x0);
        std::vector<double>& plane = v.plane < 0 ? allocated(sum_) : planeSums_[size_t(v.plane)];
        for (int c = 0; c < 3; ++c)
            plane[3 * dst + size_t(c)] += v.value[c];
    }
    lightPaths_ += tile.lightPaths;
}

double SampleFilm::sumLuminance(size_t k, size_t i) const {
    const std::vector<double>& plane = k == 0 ? sum_ : planeSums_[k - 1];
    if (plane.empty()) return 0.0;
    return Spectrum(plane[3 * i], plane[3 * i + 1], plane[3 * i + 2]).luminance();
}

void SampleFilm::endPass() {
    for (size_t k = 0; k < passStart_.size(); ++k)
        for (size_t i = 0; i < window_.area(); ++i) {
            const double now = sumLuminance(k, i), x = now - passStart_[k][i];
            passSquares_[k][i] += x * x;
            passStart_[k][i] = now;
        }
    ++passesEnded_;
}

double SampleFilm::passVariance(size_t k, size_t i) const {
    // From the ended passes only: a pass under way (cut short by Ctrl-C or a time limit) may hold a pixel's
    // own sample without its neighbours' shares, or their shares without its own sample.
    const double n = std::min(count_[i], passesEnded_);
    if (n < 2) return 0.0;
    const double mean = passStart_[k][i] / n;
    // Rounding can take the difference of two nearly equal sums below zero.
    return std::max(0.0, (passSquares_[k][i] - n * mean * mean) / (n - 1));
}

void SampleFilm::addSplat(const Splat& s, int rowLo, int rowHi) {
    // splat_ is allocated before any splat reaches here (merge, mergeSplats): bands run in parallel.
    forEachPixel(
        s.raster,
        [&](size_t dst, double w) {
            for (int c = 0; c < 3; ++c)
                splat_[3 * dst + size_t(c)] += w * s.value[c];
        },
        rowLo, rowHi);
}

void SampleFilm::mergeSplats(const std::vector<const std::vector<Splat>*>& lists, uint64_t lightPaths) {
    allocated(splat_);
    // Bands of rows, each splat listed (in the order given) in every band it reaches; then the bands in
    // parallel. 16 rows: a band holds a splat's whole footprint for filters up to radius 7.5.
    constexpr int BandRows = 16;
    const int bands = (height() + BandRows - 1) / BandRows;
    std::vector<std::vector<const Splat*>> perBand(static_cast<size_t>(std::max(bands, 0)));
    for (const auto* list : lists)
        for (const auto& s : *list) {
            const auto [ya, yb] = rowsAround(s.raster);
            if (ya > yb) continue; // off the stored rows
            for (int b = (ya - window_.y0) / BandRows; b <= (yb - window_.y0) / BandRows; ++b)
                perBand[size_t(b)].push_back(&s);
        }
    tbb::parallel_for(0, bands, [&](int b) {
        const int rowLo = window_.y0 + b * BandRows, rowHi = std::min(window_.y1, rowLo + BandRows);
        for (const auto* s : perBand[size_t(b)])
            addSplat(*s, rowLo, rowHi);
    });
    lightPaths_ += lightPaths;
}

double SampleFilm::splatWeight(double splatScale) const {
    // Light paths per pixel: the splat estimator of a pixel sums over all light paths of the image.
    return splatScale * (lightPaths_ > 0 ? double(window_.area()) / double(lightPaths_) : 0.0);
}

double SampleFilm::estimate(size_t i, size_t c, double splatWeight) const {
    const double cam = count_[i] > 0 ? sum_[3 * i + c] / count_[i] : 0.0;
    return splat_.empty() ? cam : cam + splat_[3 * i + c] * splatWeight;
}

std::vector<float> SampleFilm::develop(double splatScale) const {
    const double w = splatWeight(splatScale);
    std::vector<float> out(window_.area() * 3);
    for (size_t i = 0; i < window_.area(); ++i)
        for (size_t c = 0; c < 3; ++c)
            out[3 * i + c] = float(estimate(i, c, w));
    return out;
}

std::vector<std::vector<float>> SampleFilm::developPlanes(double splatScale) const {
    const double w = splatWeight(splatScale);
    std::vector<std::vector<float>> out(3, std::vector<float>(window_.area()));
    for (size_t c = 0; c < 3; ++c)
        for (size_t i = 0; i < window_.area(); ++i)
            out[c][i] = float(estimate(i, c, w));
    return out;
}

file::Buffer SampleFilm::toBuffer(double splatScale) const {
    file::Buffer b;
    b.width = uint32_t(width());
    b.height = uint32_t(height());
    const char* const rgbNames[] = {"R", "G", "B"};
    for (const char* c : rgbNames)
        b.channels.push_back(planeNames_.empty() ? std::string(c) : std::string("primal.") + c);
    b.planes = developPlanes(splatScale);
    for (size_t p = 0; p < planeNames_.size(); ++p)
        for (size_t c = 0; c < 3; ++c) {
            b.channels.push_back(planeNames_[p] + "." + rgbNames[c]);
            std::vector<float> plane(window_.area());
            for (size_t i = 0; i < window_.area(); ++i)
                plane[i] = count_[i] > 0 ? float(planeSums_[p][3 * i + c] / count_[i]) : 0.0f;
            b.planes.push_back(std::move(plane));
        }
    for (size_t k = 0; k < passStart_.size(); ++k) {
        b.channels.push_back((k == 0 ? std::string("primal") : planeNames_[k - 1]) + ".var");
        std::vector<float> plane(window_.area());
        for (size_t i = 0; i < window_.area(); ++i)
            // A variance beyond float's range (luminances above ~1e19) is stored as the largest float.
            plane[i] = float(std::min(passVariance(k, i), double(std::numeric_limits<float>::max())));
        b.planes.push_back(std::move(plane));
    }
    b.sampleCounts = count_;
    // Buffers of independent runs average by their work: light paths where there are any (one per camera sample for
    // BDPT; the mutations of the Markov chains, whose film may also hold the direct part's camera samples), else
    // camera samples.
    b.weight = double(lightPaths_ > 0 ? lightPaths_ : cameraSamples_);
    b.combine = "weighted-mean";
    return b;
}

} // namespace lt
