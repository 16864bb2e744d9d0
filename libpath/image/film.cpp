#include "image/film.h"

#include <cmath>

namespace lt {

SampleFilm::SampleFilm(const PerspectiveCamera& camera) : filter_(camera.film().filter) {
    const auto& f = camera.film();
    window_ = {f.cropX, f.cropY, f.cropX + f.cropWidth, f.cropY + f.cropHeight};
    sum_.assign(window_.area() * 3, 0.0);
    splat_.assign(window_.area() * 3, 0.0);
    count_.assign(window_.area(), 0);
}

template <class F> void SampleFilm::forEachPixel(const Vec2& raster, F&& f) const {
    // Pixels whose filter support contains the position: centers within the radius of it.
    const double r = filter_.radius();
    const int xa = std::max(window_.x0, int(std::ceil(raster.x - r - 0.5)));
    const int xb = std::min(window_.x1 - 1, int(std::floor(raster.x + r - 0.5)));
    const int ya = std::max(window_.y0, int(std::ceil(raster.y - r - 0.5)));
    const int yb = std::min(window_.y1 - 1, int(std::floor(raster.y + r - 0.5)));
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

void SampleFilm::merge(const TileResult& tile) {
    for (int y = tile.rect.y0; y < tile.rect.y1; ++y)
        for (int x = tile.rect.x0; x < tile.rect.x1; ++x) {
            const size_t src = size_t(y - tile.rect.y0) * size_t(tile.rect.width()) + size_t(x - tile.rect.x0);
            const size_t dst = size_t(y - window_.y0) * size_t(width()) + size_t(x - window_.x0);
            for (int c = 0; c < 3; ++c) sum_[3 * dst + size_t(c)] += tile.sum[3 * src + size_t(c)];
            count_[dst] += tile.count[src];
            cameraSamples_ += tile.count[src];
        }
    for (const auto& s : tile.splats)
        forEachPixel(s.raster, [&](size_t dst, double w) {
            for (int c = 0; c < 3; ++c) splat_[3 * dst + size_t(c)] += w * s.value[c];
        });
    lightPaths_ += tile.lightPaths;
}

std::vector<float> SampleFilm::develop() const {
    std::vector<float> out(window_.area() * 3, 0.0f);
    // Light paths per pixel: the splat estimator of a pixel sums over all light paths of the image.
    const double splatScale = lightPaths_ > 0 ? double(window_.area()) / double(lightPaths_) : 0.0;
    for (size_t i = 0; i < window_.area(); ++i)
        for (size_t c = 0; c < 3; ++c) {
            const double cam = count_[i] > 0 ? sum_[3 * i + c] / count_[i] : 0.0;
            out[3 * i + c] = float(cam + splat_[3 * i + c] * splatScale);
        }
    return out;
}

file::Buffer SampleFilm::toBuffer() const {
    file::Buffer b;
    b.width = uint32_t(width());
    b.height = uint32_t(height());
    b.channels = {"R", "G", "B"};
    const std::vector<float> rgb = develop();
    b.planes.assign(3, std::vector<float>(window_.area()));
    for (size_t i = 0; i < window_.area(); ++i)
        for (size_t c = 0; c < 3; ++c) b.planes[c][i] = rgb[3 * i + c];
    b.sampleCounts = count_;
    // Buffers of independent runs average by their work: camera samples, or for a splat-only film (the
    // Markov chains) the number of mutations.
    b.weight = double(cameraSamples_ > 0 ? cameraSamples_ : lightPaths_);
    b.combine = "weighted-mean";
    return b;
}

} // namespace lt
