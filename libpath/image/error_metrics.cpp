#include "image/error_metrics.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <limits>
#include <numeric>
#include <variant>

#include "formats/ltfile.h"
#include "image/buffer_source.h"
#include "image/image_io.h"
#include "util/error.h"

namespace lt {

namespace {

// [GDPR] (Bauszat et al. 2017, Sec. 4, after Rousselle et al. 2012): relMSE's epsilon keeps black
// reference pixels from dividing by zero.
constexpr double kRelMseEpsilon = 0.001;
// MAPE's standard definition, mean |I - ref| / |ref|, is infinite on any black reference pixel (a
// shadow, the background); like the denoising literature (e.g. Vogels et al. 2018, "relative L1") we
// add 0.01 to the denominator. Stated here because it changes the value on dark pixels.
constexpr double kMapeEpsilon = 0.01;

std::string sizeText(uint32_t w, uint32_t h) { return std::to_string(w) + "x" + std::to_string(h); }

// The planes of the channels named R, G, B (the beauty image every renderer writes).
std::array<const std::vector<float>*, 3> rgbPlanes(const file::Buffer& b, const std::string& name) {
    std::array<const std::vector<float>*, 3> planes{};
    // R, G, B; a film with further planes (a gradient-domain render, formats/SPEC.md) names its image
    // primal.R, primal.G, primal.B.
    const bool primal = std::find(b.channels.begin(), b.channels.end(), "R") == b.channels.end() &&
                        std::find(b.channels.begin(), b.channels.end(), "primal.R") != b.channels.end();
    const char* names[3] = {"R", "G", "B"};
    for (size_t c = 0; c < 3; ++c) {
        const std::string channel = (primal ? "primal." : "") + std::string(names[c]);
        const auto it = std::find(b.channels.begin(), b.channels.end(), channel);
        if (it == b.channels.end()) {
            std::string has;
            for (const auto& n : b.channels)
                has += (has.empty() ? "" : ", ") + n;
            throw Error(name + ": no channel " + channel + " (the error is measured on channels R, G, B; it has " +
                        (has.empty() ? "none" : has) + ")");
        }
        planes[c] = &b.planes[size_t(it - b.channels.begin())];
        if (planes[c]->size() != size_t(b.width) * b.height)
            throw Error(name + ": channel " + channel + " holds " + std::to_string(planes[c]->size()) +
                        " values for a " + sizeText(b.width, b.height) + " image");
    }
    return planes;
}

// NaN sorts after every number, so trimming drops NaN pixels first and the order stays a strict weak
// ordering (std::nth_element needs one; plain < with NaN is not).
bool lessNanLast(double a, double b) { return !std::isnan(a) && (std::isnan(b) || a < b); }

} // namespace

ErrorMetric parseErrorMetric(std::string_view name) {
    if (name == "relmse") return ErrorMetric::RelMSE;
    if (name == "rrmse") return ErrorMetric::RRMSE;
    if (name == "mse") return ErrorMetric::MSE;
    if (name == "mape") return ErrorMetric::MAPE;
    if (name == "smape") return ErrorMetric::SMAPE;
    throw Error("unknown error metric '" + std::string(name) + "' (relmse, rrmse, mse, mape or smape)");
}

std::string errorMetricName(ErrorMetric metric) {
    switch (metric) {
    case ErrorMetric::RelMSE:
        return "relMSE";
    case ErrorMetric::RRMSE:
        return "rRMSE";
    case ErrorMetric::MSE:
        return "MSE";
    case ErrorMetric::MAPE:
        return "MAPE";
    case ErrorMetric::SMAPE:
        return "SMAPE";
    }
    return "?";
}

Crop parseCrop(std::string_view text) {
    const auto bad = [&] {
        return Error("crop '" + std::string(text) + "' is not X,Y,W,H (whole numbers, W and H > 0)");
    };
    std::array<uint32_t, 4> v{};
    const char* p = text.data();
    const char* end = text.data() + text.size();
    for (size_t i = 0; i < 4; ++i) {
        const auto [next, ec] = std::from_chars(p, end, v[i]);
        if (ec != std::errc() || next == p) throw bad();
        p = next;
        if (i < 3) {
            if (p == end || *p != ',') throw bad();
            ++p;
        }
    }
    if (p != end || v[2] == 0 || v[3] == 0) throw bad();
    return {v[0], v[1], v[2], v[3]};
}

ErrorReference::ErrorReference(file::Buffer reference, std::string name)
    : reference_(std::move(reference)), name_(std::move(name)) {
    const auto rgb = rgbPlanes(reference_, name_);
    // A reference with a NaN or Inf makes every error NaN or Inf: name the first bad pixel so it can be
    // found (and the reference re-rendered) rather than reporting a meaningless curve.
    const char* names[3] = {"R", "G", "B"};
    for (uint32_t y = 0; y < reference_.height; ++y)
        for (uint32_t x = 0; x < reference_.width; ++x)
            for (size_t c = 0; c < 3; ++c) {
                const float v = (*rgb[c])[size_t(y) * reference_.width + x];
                if (!std::isfinite(v))
                    throw Error(name_ + ": the reference has " + (std::isnan(v) ? "a NaN" : "an infinite value") +
                                " at pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") in channel " +
                                names[c]);
            }
}

std::vector<double> ErrorReference::pixelErrors(const file::Buffer& image, const std::string& imageName,
                                                ErrorMetric metric) const {
    if (image.width != reference_.width || image.height != reference_.height)
        throw Error("cannot compare " + imageName + " with " + name_ + ": sizes differ (" +
                    sizeText(image.width, image.height) + " and " + sizeText(reference_.width, reference_.height) +
                    ")");
    const auto in = rgbPlanes(image, imageName);
    const auto ref = rgbPlanes(reference_, name_);
    std::vector<double> errors(size_t(image.width) * image.height);
    for (size_t p = 0; p < errors.size(); ++p) {
        double e = 0;
        switch (metric) {
        case ErrorMetric::RelMSE:
        case ErrorMetric::RRMSE: {
            // [GDPR] (Bauszat et al. 2017) Sec. 4: "the mean over all pixel errors given by
            // sum_c (I_k^c - ref_k^c)^2 / (mean(ref_k^c)^2 + eps) where ... mean(ref_k^c) is the mean of
            // all color channels of the reference pixel, and eps = 0.001". The overline is over ref_k^c
            // and the square outside it: the denominator is the SQUARED CHANNEL MEAN of the reference
            // pixel, not the mean of the squared channels (they differ on coloured pixels).
            const double mean = (double((*ref[0])[p]) + (*ref[1])[p] + (*ref[2])[p]) / 3;
            const double denominator = mean * mean + kRelMseEpsilon;
            for (size_t c = 0; c < 3; ++c) {
                const double d = double((*in[c])[p]) - (*ref[c])[p];
                e += d * d / denominator;
            }
            break;
        }
        case ErrorMetric::MSE:
            // Mean squared error over all pixel-channel values: the per-pixel term is the channel mean.
            for (size_t c = 0; c < 3; ++c) {
                const double d = double((*in[c])[p]) - (*ref[c])[p];
                e += d * d / 3;
            }
            break;
        case ErrorMetric::MAPE:
            // Mean absolute percentage error (as a fraction, not x100) over all pixel-channel values,
            // |I - ref| / (|ref| + 0.01): see kMapeEpsilon.
            for (size_t c = 0; c < 3; ++c) {
                const double r = (*ref[c])[p];
                e += std::abs(double((*in[c])[p]) - r) / (std::abs(r) + kMapeEpsilon) / 3;
            }
            break;
        case ErrorMetric::SMAPE:
            // Symmetric MAPE (Makridakis 1993; the form with range [0, 2]) over all pixel-channel values:
            // 2 |I - ref| / (|I| + |ref|), and 0 where both are 0 (a black pixel matched exactly).
            for (size_t c = 0; c < 3; ++c) {
                const double i = (*in[c])[p], r = (*ref[c])[p];
                const double sum = std::abs(i) + std::abs(r);
                if (sum > 0) e += 2 * std::abs(i - r) / sum / 3;
            }
            break;
        }
        errors[p] = e;
    }
    return errors;
}

ImageError aggregatePixelErrors(std::vector<double> pixelErrors, uint32_t width, uint32_t height,
                                const ErrorOptions& options) {
    if (!(options.trim >= 0 && options.trim < 1))
        throw Error("trim fraction " + std::to_string(options.trim) + " is outside [0, 1)");
    const Crop crop = options.crop.value_or(Crop{0, 0, width, height});
    if (uint64_t(crop.x) + crop.width > width || uint64_t(crop.y) + crop.height > height || crop.width == 0 ||
        crop.height == 0)
        throw Error("crop " + std::to_string(crop.x) + "," + std::to_string(crop.y) + "," + std::to_string(crop.width) +
                    "," + std::to_string(crop.height) + " does not fit the " + sizeText(width, height) + " image");
    std::vector<double> kept;
    kept.reserve(size_t(crop.width) * crop.height);
    for (uint32_t y = crop.y; y < crop.y + crop.height; ++y)
        for (uint32_t x = crop.x; x < crop.x + crop.width; ++x)
            kept.push_back(pixelErrors[size_t(y) * width + x]);

    ImageError result;
    // floor: trimming never drops more than asked; trim < 1 keeps at least one pixel.
    result.trimmed = size_t(std::floor(options.trim * double(kept.size())));
    result.pixels = kept.size() - result.trimmed;
    if (result.trimmed > 0)
        std::nth_element(kept.begin(), kept.begin() + ptrdiff_t(result.pixels), kept.end(), lessNanLast);
    const double sum = std::accumulate(kept.begin(), kept.begin() + ptrdiff_t(result.pixels), 0.0);
    result.value = sum / double(result.pixels);
    if (options.metric == ErrorMetric::RRMSE) result.value = std::sqrt(result.value);
    return result;
}

ImageError ErrorReference::error(const file::Buffer& image, const std::string& imageName,
                                 const ErrorOptions& options) const {
    return aggregatePixelErrors(pixelErrors(image, imageName, options.metric), image.width, image.height, options);
}

double ErrorReference::scaleToReference(const file::Buffer& image, const std::string& imageName,
                                        const std::optional<Crop>& crop) const {
    const auto in = rgbPlanes(image, imageName);
    const auto ref = rgbPlanes(reference_, name_);
    const Crop c = crop.value_or(Crop{0, 0, image.width, image.height});
    double sumIn = 0, sumRef = 0;
    for (uint32_t y = c.y; y < c.y + c.height && y < image.height; ++y)
        for (uint32_t x = c.x; x < c.x + c.width && x < image.width; ++x)
            for (size_t k = 0; k < 3; ++k) {
                sumIn += (*in[k])[size_t(y) * image.width + x];
                sumRef += (*ref[k])[size_t(y) * image.width + x];
            }
    return sumIn > 0 ? sumRef / sumIn : std::numeric_limits<double>::quiet_NaN();
}

std::optional<double> ErrorRow::efficiency() const {
    if (!wallSeconds) return std::nullopt;
    return 1 / (error.value * *wallSeconds);
}

ErrorCurve measureErrorCurve(const std::string& path, const ErrorReference& reference, const ErrorOptions& options) {
    ErrorCurve curve;
    const auto makeRow = [](std::string label) {
        ErrorRow row;
        row.label = std::move(label);
        return row;
    };
    // Measures one estimate into `row` (as is and rescaled to the reference's mean) and keeps its per-pixel
    // terms as the latest "final" image.
    auto measure = [&](ErrorRow row, const file::Buffer& buffer, const std::string& name) {
        std::vector<double> terms = reference.pixelErrors(buffer, name, options.metric);
        row.error = aggregatePixelErrors(terms, buffer.width, buffer.height, options);
        curve.finalErrors = std::move(terms);
        curve.width = buffer.width;
        curve.height = buffer.height;
        row.scale = reference.scaleToReference(buffer, name, options.crop);
        if (std::isfinite(row.scale)) {
            file::Buffer rescaled = buffer;
            for (auto& plane : rescaled.planes)
                for (auto& v : plane)
                    v = float(v * row.scale);
            row.rescaledError = reference.error(rescaled, name, options);
        } else {
            row.rescaledError = row.error;
        }
        return row;
    };

    if (path != "-" && isExrFile(path)) {
        const BufferSource source = loadBuffer(path);
        curve.name = source.name;
        curve.rows.push_back(measure(makeRow("EXR"), source.buffer, source.name));
        return curve;
    }

    // Streamed: a long run can hold many full-size snapshots.
    file::Reader reader(path, file::FileKind::Buffer);
    curve.name = reader.name();
    size_t snapshots = 0;
    std::optional<ErrorRow> final;
    std::vector<double> finalErrors, lastSnapshotErrors;
    const file::StatTable* run = nullptr;
    std::vector<file::StatTable> stats;
    for (;;) {
        file::Chunk chunk = reader.next();
        if (std::holds_alternative<file::End>(chunk)) break;
        if (const auto* s = std::get_if<file::Snapshot>(&chunk)) {
            ++snapshots;
            ErrorRow row = makeRow("SNAP " + std::to_string(snapshots));
            row.wallSeconds = s->wallSeconds;
            row.cpuSeconds = s->cpuSeconds;
            row.samples = s->samples;
            curve.rows.push_back(
                measure(std::move(row), s->buffer, curve.name + " (snapshot " + std::to_string(snapshots) + ")"));
            lastSnapshotErrors = curve.finalErrors;
        } else if (const auto* b = std::get_if<file::Buffer>(&chunk)) {
            // One BUFR per file (SPEC.md "SNAP"); should there be more, the last is the result, as for
            // every tool that develops a file.
            final = measure(makeRow("BUFR"), *b, curve.name);
            finalErrors = curve.finalErrors;
        } else if (auto* t = std::get_if<file::StatTable>(&chunk)) {
            stats.push_back(std::move(*t));
        }
    }
    for (auto& row : curve.rows)
        row.label += " of " + std::to_string(snapshots);
    if (!final) {
        if (curve.rows.empty()) throw Error(curve.name + ": holds no buffer (no BUFR or SNAP chunk)");
        curve.finalErrors = std::move(lastSnapshotErrors);
        return curve;
    }
    // The final buffer's time and samples: the STAT table "run" (SPEC.md "INFO"), written after it.
    for (const auto& t : stats)
        if (t.name == "run") run = &t;
    if (run) {
        const auto value = [&](const std::string& row) -> std::optional<double> {
            const auto it = std::find(run->rows.begin(), run->rows.end(), row);
            if (it == run->rows.end() || run->columns.empty()) return std::nullopt;
            const auto& values = run->values[size_t(it - run->rows.begin())];
            if (values.empty()) return std::nullopt;
            return values[0];
        };
        final->wallSeconds = value("wall_seconds");
        final->cpuSeconds = value("cpu_seconds");
        if (const auto samples = value("samples"); samples && *samples >= 0) final->samples = uint64_t(*samples);
    }
    curve.rows.push_back(std::move(*final));
    curve.finalErrors = std::move(finalErrors);
    return curve;
}

} // namespace lt
