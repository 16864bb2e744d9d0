#include "image/buffer_merge.h"

#include <algorithm>
#include <set>

#include "image/image_io.h"
#include "util/error.h"

namespace lt {

namespace {

std::string sizeText(const file::Buffer& b) { return std::to_string(b.width) + "x" + std::to_string(b.height); }

std::string channelText(const std::vector<std::string>& channels) {
    std::string s;
    for (const auto& c : channels)
        s += (s.empty() ? "" : ",") + c;
    return s;
}

} // namespace

file::Buffer mergeBuffers(std::span<const file::Buffer> buffers, std::span<const std::string> names) {
    if (buffers.empty()) throw Error("no buffers to merge");
    if (names.size() != buffers.size()) throw Error("mergeBuffers: one name per buffer expected");
    for (size_t i = 0; i < buffers.size(); ++i)
        checkBuffer(buffers[i], names[i]);
    // One buffer is itself, whatever its weight (a run stopped before its first sample still develops).
    if (buffers.size() == 1) return buffers[0];
    const file::Buffer& first = buffers[0];
    const std::set<std::string> channelSet(first.channels.begin(), first.channels.end());
    for (size_t i = 1; i < buffers.size(); ++i) {
        const file::Buffer& b = buffers[i];
        const std::string both = names[0] + " and " + names[i];
        if (b.width != first.width || b.height != first.height)
            throw Error("cannot merge " + both + ": sizes differ (" + sizeText(first) + " and " + sizeText(b) + ")");
        if (std::set<std::string>(b.channels.begin(), b.channels.end()) != channelSet)
            throw Error("cannot merge " + both + ": channels differ (" + channelText(first.channels) + " and " +
                        channelText(b.channels) + ")");
        if (b.combine != first.combine)
            throw Error("cannot merge " + both + ": combine rules differ (" + first.combine + " and " + b.combine +
                        ")");
    }
    if (first.combine != "weighted-mean" && first.combine != "sum")
        throw Error(names[0] + ": unknown combine rule '" + first.combine + "'");

    file::Buffer out;
    out.width = first.width;
    out.height = first.height;
    out.channels = first.channels;
    out.combine = first.combine;
    out.weight = 0;
    for (const auto& b : buffers)
        out.weight += b.weight;
    const bool mean = first.combine == "weighted-mean";
    if (mean && !(out.weight > 0))
        throw Error("cannot merge " + names[0] + " and the others: weighted mean of total weight 0");

    const size_t pixels = size_t(out.width) * size_t(out.height);
    std::vector<double> acc(pixels);
    for (const auto& channel : out.channels) {
        std::fill(acc.begin(), acc.end(), 0.0);
        for (const auto& b : buffers) {
            // A buffer of weight 0 (e.g. a run stopped before its first sample) contributes nothing,
            // not 0 * NaN.
            if (mean && b.weight == 0) continue;
            const double w = mean ? b.weight : 1.0;
            const auto& plane =
                b.planes[size_t(std::find(b.channels.begin(), b.channels.end(), channel) - b.channels.begin())];
            for (size_t p = 0; p < pixels; ++p)
                acc[p] += w * double(plane[p]);
        }
        std::vector<float>& plane = out.planes.emplace_back(pixels);
        for (size_t p = 0; p < pixels; ++p)
            plane[p] = float(mean ? acc[p] / out.weight : acc[p]);
    }
    if (std::all_of(buffers.begin(), buffers.end(), [](const file::Buffer& b) { return !b.sampleCounts.empty(); })) {
        out.sampleCounts.assign(pixels, 0);
        for (const auto& b : buffers)
            for (size_t p = 0; p < pixels; ++p)
                out.sampleCounts[p] += b.sampleCounts[p];
    }
    return out;
}

} // namespace lt
