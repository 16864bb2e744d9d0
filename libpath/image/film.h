// The film: accumulates the pixel measurement I_j = integral of h_j(x) L(x) over the image plane, with h_j
// the normalized pixel filter around pixel j (image/filter_density.h), from two kinds of samples:
// * camera samples, drawn from h_j and credited to pixel j alone (estimate: mean of L);
// * splats (light tracing), each spread over the pixels around it with weights h_j; a splat estimator
//   is a sum over light paths, so it is divided by the number of light paths per pixel.
// Only the crop window is stored. Work is merged tile by tile in a fixed order, so the result does not
// depend on the number of threads.
// Besides the primal image a film may hold further named RGB planes (a gradient-domain estimator's "dx",
// "dy", "direct": formats/SPEC.md): each pixel's value is the sum of what camera samples gave it,
// divided by the pixel's own camera samples.
// A film with further planes also estimates, per pixel, the variance of one pass's value of each plane
// (primal included), in luminance: the gradient-domain estimators give every pixel one value per sample
// pass, assembled from its own sample and its neighbours' shifts (G-PT) or from its tile (path reusing),
// and the passes are independent, so the passes' values are i.i.d. draws of the pixel's estimate.
// The render loop says where a pass ends (endPass); the film keeps each pixel's luminance at the pass's
// start and the sum of the squared values of the ended passes, and writes the sample variance
// s^2 = (sum x_p^2 - n mean^2) / (n - 1) as channel NAME.var (the variance of the pixel's mean is
// s^2 / n, n its sample count).
#pragma once

#include <climits>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "formats/records.h"
#include "image/filter_density.h"
#include "math/spectrum.h"
#include "path/splat.h"
#include "scene/camera.h"

namespace lt {

struct PixelRect {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0; // [x0, x1) x [y0, y1), in full-film pixel coordinates
    [[nodiscard]] int width() const { return x1 - x0; }
    [[nodiscard]] int height() const { return y1 - y0; }
    [[nodiscard]] size_t area() const { return size_t(width()) * size_t(height()); }
    [[nodiscard]] bool contains(int x, int y) const { return x >= x0 && x < x1 && y >= y0 && y < y1; }
};

// The pixels a film stores and renders: its crop window, in full-film coordinates.
[[nodiscard]] inline PixelRect cropWindow(const Film& f) {
    return {f.cropX, f.cropY, f.cropX + f.cropWidth, f.cropY + f.cropHeight};
}

// What one piece of work (a tile, some samples per pixel) produced.
struct TileResult {
    PixelRect rect;
    std::vector<double> sum;     // 3 per pixel of rect: sum of camera estimates
    std::vector<uint32_t> count; // camera samples per pixel of rect
    std::vector<Splat> splats; // anywhere on the film
    uint64_t lightPaths = 0;   // light subpaths traced (one per camera sample for BDPT)
    // Values of the further planes (plane -1: the primal image), at pixels (full-film coordinates) that
    // may lie outside rect.
    struct PlanePixel {
        int plane = 0, x = 0, y = 0;
        Spectrum value;
    };
    std::vector<PlanePixel> planeValues;
};

class SampleFilm {
public:
    // `planes`: the names of the planes besides the primal image (none: an RGB film).
    explicit SampleFilm(const PerspectiveCamera& camera, std::vector<std::string> planes = {});

    [[nodiscard]] const PixelRect& window() const { return window_; }
    [[nodiscard]] int width() const { return window_.width(); }
    [[nodiscard]] int height() const { return window_.height(); }
    [[nodiscard]] const FilterDensity& filter() const { return filter_; }
    [[nodiscard]] const std::vector<std::string>& planes() const { return planeNames_; }

    // A camera sample's raster position for pixel (x, y) (full-film coordinates).
    [[nodiscard]] Vec2 sampleRaster(int x, int y, const Vec2& u) const {
        return Vec2(x + 0.5, y + 0.5) + filter_.sample(u);
    }

    void merge(const TileResult& tile);
    // Every pixel received its value of one more sample pass (films with further planes: the pass's values
    // enter the variance estimate; nothing otherwise).
    void endPass();
    // Adds the splats of several lists (the Markov chains' rounds) and their light paths, in parallel over
    // bands of rows: each pixel still receives the splats in the order given, list by list, so the film
    // is the same, bit for bit, as merging the lists one after another, for any thread count. Runs in the
    // caller's TBB arena.
    void mergeSplats(const std::vector<const std::vector<Splat>*>& lists, uint64_t lightPaths);
    // Sum of the stored pixels' filters h_j at a raster position: 1 inside the image for box and tent,
    // within about 1 % for the truncated gaussian, less near the border. The Markov chains' b integrates
    // over raster positions, so seed paths of camera strategies (drawn from h_j around their pixel) are
    // weighted by its inverse.
    [[nodiscard]] double filterSum(const Vec2& raster) const;

    // The current estimate, RGB float, rows top to bottom, crop window only. `splatScale` multiplies the
    // splats: the Markov chains splat with b = 1 and give their current estimate of b here, when the film
    // is read (mcmc/normalization.h).
    [[nodiscard]] std::vector<float> develop(double splatScale = 1) const;
    // The same estimate as three planes R, G, B (a file buffer's layout).
    [[nodiscard]] std::vector<std::vector<float>> developPlanes(double splatScale = 1) const;
    // Camera samples per pixel (crop window).
    [[nodiscard]] const std::vector<uint32_t>& sampleCounts() const { return count_; }
    [[nodiscard]] uint64_t lightPaths() const { return lightPaths_; }
    [[nodiscard]] uint64_t cameraSamples() const { return cameraSamples_; }
    // The developed image as a file buffer: channels R, G, B (with further planes: "primal.R" ... and
    // "NAME.R/G/B" for each plane, then "primal.var" and "NAME.var"), per-pixel sample counts, and the
    // number of camera samples as its merge weight (buffers of independent runs average by it). The
    // variances leave out a pass under way when the buffer is made.
    [[nodiscard]] file::Buffer toBuffer(double splatScale = 1) const;

private:
    // The stored rows [first, last] whose pixels' filter supports can contain the raster position (first >
    // last when none).
    [[nodiscard]] std::pair<int, int> rowsAround(const Vec2& raster) const;
    // Calls f(index, h_j) for every stored pixel j whose filter support contains the raster position, in
    // the rows [rowLo, rowHi) only.
    template <class F> void forEachPixel(const Vec2& raster, F&& f, int rowLo = INT_MIN, int rowHi = INT_MAX) const;
    // Luminance of pixel i's sum in plane k (0 the primal image, k > 0 planes k - 1).
    [[nodiscard]] double sumLuminance(size_t k, size_t i) const;
    // Sample variance of one pass's value of plane k at pixel i, over the ended passes (0 with fewer than two).
    [[nodiscard]] double passVariance(size_t k, size_t i) const;
    // A splat spread over the pixels of rows [rowLo, rowHi) it reaches.
    void addSplat(const Splat& s, int rowLo, int rowHi);
    // What a splat adds to a pixel per unit of its value when the film is read (develop's `splatScale` over
    // the light paths per pixel).
    [[nodiscard]] double splatWeight(double splatScale) const;
    // The current estimate of channel c of stored pixel i, given splatWeight.
    [[nodiscard]] double estimate(size_t i, size_t c, double splatWeight) const;
    // `sums` (sum_ or splat_) with room for every stored pixel: the two are allocated on their first use, so
    // a film that only takes camera samples (path tracing) or only splats (the Markov chains) holds one.
    std::vector<double>& allocated(std::vector<double>& sums);

    PixelRect window_;
    FilterDensity filter_;
    // Sums of camera estimates and of splats, 3 per stored pixel once allocated (empty until first used).
    std::vector<double> sum_, splat_;
    std::vector<std::string> planeNames_;
    std::vector<std::vector<double>> planeSums_; // per plane, 3 per stored pixel
    std::vector<uint32_t> count_;
    uint64_t lightPaths_ = 0, cameraSamples_ = 0;
    // Per plane (0 the primal image, then the further planes), per pixel: the luminance of the sum when the
    // current pass began, and the sum over ended passes of each pass's value squared. Empty without planes.
    std::vector<std::vector<double>> passStart_, passSquares_;
    uint32_t passesEnded_ = 0;
};

} // namespace lt
