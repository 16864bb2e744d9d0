#include "image/filter_density.h"

#include <algorithm>
#include <cmath>

namespace lt {

namespace {
constexpr int GaussianBins = 1024;
}

FilterDensity::FilterDensity(const PixelFilter& filter) : type_(filter.type), radius_(filter.radius) {
    if (type_ == PixelFilter::Type::Gaussian) {
        // Mitsuba's gaussian (minus its value at the radius), tabulated in equal bins.
        pdf_.resize(GaussianBins);
        cdf_.resize(GaussianBins + 1, 0.0);
        const double w = 2 * radius_ / GaussianBins;
        for (int i = 0; i < GaussianBins; ++i) {
            const double x = -radius_ + (i + 0.5) * w;
            pdf_[size_t(i)] = std::max(0.0, filter.eval(x, 0) / filter.eval(0, 0));
            cdf_[size_t(i) + 1] = cdf_[size_t(i)] + pdf_[size_t(i)] * w;
        }
        const double total = cdf_.back();
        for (auto& c : cdf_) c /= total;
        for (auto& p : pdf_) p /= total;
    }
}

double FilterDensity::sample1D(double u) const {
    switch (type_) {
    case PixelFilter::Type::Box: return (u - 0.5) * 2 * radius_;
    case PixelFilter::Type::Tent:
        // Inverse CDF of the tent (1 - |x|/r) / r on [-r, r].
        return u < 0.5 ? radius_ * (-1 + std::sqrt(2 * u)) : radius_ * (1 - std::sqrt(2 * (1 - u)));
    case PixelFilter::Type::Gaussian: {
        const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
        const size_t i = std::min<size_t>(size_t(std::max<ptrdiff_t>(it - cdf_.begin() - 1, 0)), GaussianBins - 1);
        const double within = (u - cdf_[i]) / std::max(cdf_[i + 1] - cdf_[i], 1e-300);
        return -radius_ + (double(i) + std::clamp(within, 0.0, 1.0)) * (2 * radius_ / GaussianBins);
    }
    }
    return 0;
}

double FilterDensity::eval1D(double x) const {
    const double ax = std::abs(x);
    if (ax >= radius_) return 0;
    switch (type_) {
    case PixelFilter::Type::Box: return 0.5 / radius_;
    case PixelFilter::Type::Tent: return (1 - ax / radius_) / radius_;
    case PixelFilter::Type::Gaussian: {
        const int i = std::clamp(int((x + radius_) / (2 * radius_) * GaussianBins), 0, GaussianBins - 1);
        return pdf_[size_t(i)];
    }
    }
    return 0;
}

} // namespace lt
