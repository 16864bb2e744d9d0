#include "image/snapshot_schedule.h"

#include <cmath>

#include "util/error.h"
#include "util/number_text.h"

namespace lt {

namespace {

std::vector<double> parseList(const std::string& spec, const char* what) {
    std::vector<double> out;
    size_t pos = 0;
    while (pos <= spec.size()) {
        const size_t comma = spec.find(',', pos);
        const std::string tok = spec.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
        const double v = numberFromText(tok).value_or(0);
        if (!(v > 0) || !std::isfinite(v))
            throw Error(std::string("snapshot ") + what + " must be positive numbers separated by commas, got '" + spec + "'");
        if (!out.empty() && !(v > out.back()))
            throw Error(std::string("snapshot ") + what + " must increase, got '" + spec + "'");
        out.push_back(v);
        if (comma == std::string::npos) break;
        pos = comma + 1;
    }
    return out;
}

} // namespace

SnapshotSchedule SnapshotSchedule::parseTimes(const std::string& spec) {
    SnapshotSchedule s;
    if (spec.rfind("doubling", 0) == 0) {
        s.kind_ = Kind::Doubling;
        if (spec.size() > 8) {
            if (spec[8] != ':') throw Error("snapshot times: expected doubling or doubling:START, got '" + spec + "'");
            const auto v = parseList(spec.substr(9), "start");
            if (v.size() != 1) throw Error("snapshot times: doubling takes one start time, got '" + spec + "'");
            s.doubling_ = v[0];
        }
        return s;
    }
    s.kind_ = Kind::Times;
    s.points_ = parseList(spec, "times");
    return s;
}

SnapshotSchedule SnapshotSchedule::parseSamples(const std::string& spec) {
    SnapshotSchedule s;
    s.kind_ = Kind::Samples;
    s.points_ = parseList(spec, "sample counts");
    return s;
}

bool SnapshotSchedule::due(double seconds, double samplesPerPixel) {
    switch (kind_) {
    case Kind::None: return false;
    case Kind::Doubling:
        if (seconds < doubling_) return false;
        while (doubling_ <= seconds) doubling_ *= 2;
        return true;
    case Kind::Times:
    case Kind::Samples: {
        const double now = kind_ == Kind::Times ? seconds : samplesPerPixel;
        if (next_ >= points_.size() || now < points_[next_]) return false;
        while (next_ < points_.size() && points_[next_] <= now) ++next_;
        return true;
    }
    }
    return false;
}

} // namespace lt
