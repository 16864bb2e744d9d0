// The error of an image against a reference, per pixel and over the image (optionally a crop, optionally
// without its worst pixels), and the error of every estimate a buffer file holds (each SNAP snapshot,
// then the final BUFR) for error-against-time curves. What lt-error computes; the papers' convergence
// plots (relMSE against seconds, efficiency = 1 / (error x time), [GDPR] Sec. 4 and Fig. 5, 6) are made
// of these numbers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "formats/records.h"

namespace lt {

enum class ErrorMetric { RelMSE, RRMSE, MSE, MAPE, SMAPE };

// "relmse", "rrmse", "mse", "mape", "smape" (the command-line names); anything else throws lt::Error.
[[nodiscard]] ErrorMetric parseErrorMetric(std::string_view name);
// The name for tables, plots and CSV: "relMSE", "rRMSE", "MSE", "MAPE", "SMAPE".
[[nodiscard]] std::string errorMetricName(ErrorMetric metric);

// A rectangle of pixels: columns [x, x + width), rows [y, y + height).
struct Crop {
    uint32_t x = 0, y = 0, width = 0, height = 0;
};
// "X,Y,W,H" with W, H > 0; anything else throws lt::Error quoting the text.
[[nodiscard]] Crop parseCrop(std::string_view text);

struct ErrorOptions {
    ErrorMetric metric = ErrorMetric::RelMSE;
    double trim = 0;          // fraction in [0, 1) of the pixels (of the crop) with the largest error to drop
    std::optional<Crop> crop; // the whole image when empty
};

struct ImageError {
    double value = 0;   // the metric over the pixels kept
    size_t pixels = 0;  // pixels the value averages (crop minus trimmed)
    size_t trimmed = 0; // pixels dropped by ErrorOptions::trim: floor(trim * pixels of the crop)
};

// A reference image checked once (R, G, B present, every R, G, B value finite) against which any number
// of images (every snapshot of every input) are measured.
class ErrorReference {
public:
    // `name` is the file it came from; errors name it. Throws lt::Error for a missing R, G or B channel
    // or a NaN or infinite value (naming the first such pixel in row-major order).
    ErrorReference(file::Buffer reference, std::string name);

    // The per-pixel term of `metric` for every pixel of `image` (width * height, row-major): the value
    // whose mean over pixels is the metric, before rRMSE's square root (so for rRMSE it is relMSE's
    // term). Throws lt::Error if the image lacks R, G or B or its size differs from the reference's.
    [[nodiscard]] std::vector<double> pixelErrors(const file::Buffer& image, const std::string& imageName,
                                                  ErrorMetric metric) const;

    // The metric over the crop (checked against the image size) without the trimmed pixels.
    [[nodiscard]] ImageError error(const file::Buffer& image, const std::string& imageName,
                                   const ErrorOptions& options) const;
    // The factor that brings the image's mean over the crop (R + G + B) to the reference's: 1 for an image
    // whose scale is right. A Markov chain's image carries its normalization's error as such a factor,
    // so the metric of the rescaled image is the error that is not scale (lt-error's "rescaled" column).
    // NaN for an image whose crop mean is not positive.
    [[nodiscard]] double scaleToReference(const file::Buffer& image, const std::string& imageName,
                                          const std::optional<Crop>& crop) const;

    [[nodiscard]] const file::Buffer& buffer() const { return reference_; }
    [[nodiscard]] const std::string& name() const { return name_; }

private:
    file::Buffer reference_;
    std::string name_;
};

// The metric over pixel terms of the crop of a width x height image, trimmed: what
// ErrorReference::error does once it has the terms. Exposed so a caller holding the terms (lt-error
// writing a --map) does not compute them twice.
[[nodiscard]] ImageError aggregatePixelErrors(std::vector<double> pixelErrors, uint32_t width, uint32_t height,
                                              const ErrorOptions& options);

// One estimate of a file measured: a snapshot or the final image.
struct ErrorRow {
    std::string label;                 // "SNAP 2 of 5", "BUFR" (the final buffer) or "EXR"
    std::optional<double> wallSeconds; // when the estimate was made; unknown for an EXR
    std::optional<double> cpuSeconds;
    std::optional<uint64_t> samples; // samples (or mutations) so far
    ImageError error;
    double scale = 1;         // ErrorReference::scaleToReference
    ImageError rescaledError; // the metric of the image times `scale`
    // 1 / (error x wall time) ([GDPR] Sec. 4, after Veach 1998); unknown without a time.
    [[nodiscard]] std::optional<double> efficiency() const;
};

struct ErrorCurve {
    std::string name;                // the input as errors name it
    std::vector<ErrorRow> rows;      // snapshots in file order, then the final image
    std::vector<double> finalErrors; // per-pixel terms of the final image (ErrorReference::pixelErrors)
    uint32_t width = 0, height = 0;
};

// Every estimate in `path`: an lt buffer file gives one row per SNAP snapshot (time, CPU time and
// samples from the snapshot) and one for its final BUFR (time and samples from the STAT table "run",
// unknown without it); a file without a BUFR ends with its last snapshot. An EXR gives one row without
// time. The file is streamed, so only one buffer is held at a time.
[[nodiscard]] ErrorCurve measureErrorCurve(const std::string& path, const ErrorReference& reference,
                                           const ErrorOptions& options);

} // namespace lt
