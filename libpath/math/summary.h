// Minimum, mean and maximum of a stream of values: the one-line statistic lt-inspect shows for path
// weights, sample counts and pixel values (and what lt-error or a test may want for the same).
#pragma once

#include <algorithm>
#include <cstddef>
#include <limits>

namespace lt {

struct Summary {
    size_t count = 0;
    double min = std::numeric_limits<double>::infinity();
    double max = -std::numeric_limits<double>::infinity();
    double sum = 0;

    // NaN never wins min or max (it compares false) but does reach the sum, so a NaN shows in the mean.
    void add(double v) {
        ++count;
        min = std::min(min, v);
        max = std::max(max, v);
        sum += v;
    }
    [[nodiscard]] double mean() const { return count ? sum / double(count) : 0.0; }
};

} // namespace lt
