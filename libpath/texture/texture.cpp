// Texture evaluation with Mitsuba 0.5's semantics, so that scenes written for Mitsuba look the same.
//
// uv conventions (Mitsuba 0.5, src/librender/texture.cpp, Texture2D::eval): a 2D texture is looked up at
// uv' = uv * (uscale, vscale) + (uoffset, voffset). Mitsuba's MIP map (include/mitsuba/render/mipmap.h,
// evalBilinear) then addresses texel (u' * width - 0.5, v' * height - 0.5), with row 0 the first row of
// the image file, i.e. its top. The familiar "origin at the bottom-left" of OBJ files comes from the OBJ
// loader flipping v (Mitsuba's obj `flipTexCoords`, default true; our obj_loader.cpp does the same),
// not from the texture; PLY and serialized uvs are used as stored.
#include <strings.h>

#include <algorithm>
#include <cctype>
#include <cmath>

#include "util/error.h"
#include "texture/image_file.h"
#include "texture/texture.h"

namespace lt {

Vec2 Texture::luminanceGradient(const Vec2& uv) const {
    constexpr double h = 1e-4;
    return {(eval({uv.x + h, uv.y}).luminance() - eval({uv.x - h, uv.y}).luminance()) / (2 * h),
            (eval({uv.x, uv.y + h}).luminance() - eval({uv.x, uv.y - h}).luminance()) / (2 * h)};
}

Spectrum CheckerboardTexture::eval(const Vec2& uv) const {
    // Mitsuba 0.5 src/textures/checkerboard.cpp: color0 where int(2u') and int(2v') have the same parity,
    // so one unit of uv' holds 2x2 checks. The conversion truncates toward zero (a C cast, not floor),
    // which makes the checks around u' = 0 or v' = 0 twice as wide; we keep that to match Mitsuba.
    const double u = uv.x * scale_.x + offset_.x;
    const double v = uv.y * scale_.y + offset_.y;
    if (!std::isfinite(u) || !std::isfinite(v)) return color1_; // undefined in Mitsuba (int cast of NaN)
    const double parity = std::fmod(std::trunc(2 * u) + std::trunc(2 * v), 2.0);
    return parity == 0 ? color0_ : color1_;
}

namespace {

// IEC 61966-2-1 (sRGB) decoding, as Mitsuba's Bitmap uses for gamma = -1.
float srgbToLinear(float v) { return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f); }

} // namespace

BitmapTexture::BitmapTexture(const std::string& filename, double gamma, const Vec2& offset, const Vec2& scale,
                             const std::string& channel, const BitmapLookup& lookup)
    : lookup_(lookup), offset_(offset), scale_(scale) {
    // Mitsuba's bitmap `gamma`: 0 (the default) detects the encoding from the file, -1 forces the sRGB
    // curve, a positive value g decodes as value^g (1 = linear).
    if (!(gamma == 0 || gamma == -1 || gamma > 0))
        throw Error(filename + ": gamma " + std::to_string(gamma) +
                    " is not supported (use -1 for sRGB, 0 for "
                    "automatic or a positive exponent)");

    const ImageFile image = readImageFile(filename);
    width_ = image.width;
    height_ = image.height;
    const int channels = image.channels;
    const std::vector<float>& pixels = image.pixels;

    // Automatic detection, as Mitsuba's Bitmap does: integer formats (PNG, JPEG, 8- and 16-bit TIFF ...)
    // hold sRGB-encoded values unless the file says it is linear; float formats (EXR, HDR, PFM) are linear.
    const auto iequals = [](const std::string& a, const char* b) { return strcasecmp(a.c_str(), b) == 0; };
    int only = -1; // the one channel read, or -1 for colour (or luminance)
    if (!channel.empty()) {
        std::string names;
        for (int c = 0; c < image.channels; ++c) {
            // Mitsuba names a one-channel image's channel "l" (luminance); OpenImageIO calls it "y".
            const std::string& name = image.channelNames[size_t(c)];
            const bool luminance = iequals(channel, "l") && iequals(name, "y");
            if (iequals(name, channel.c_str()) || luminance) only = c;
            std::string lower = name;
            std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char ch) { return std::tolower(ch); });
            names += (c ? ", " : "") + lower;
        }
        if (only < 0) throw Error(filename + ": no channel '" + channel + "' (it has " + names + ")");
    }
    const bool alpha = only >= 0 && iequals(channel, "a");
    const bool useSrgb = !alpha && (gamma == -1 || (gamma == 0 && !image.floatFormat && !image.saysLinear));
    const bool usePower = !alpha && gamma > 0 && gamma != 1;
    auto decode = [&](float v) {
        if (useSrgb) return srgbToLinear(v);
        if (usePower) return std::copysign(std::pow(std::abs(v), float(gamma)), v);
        return v;
    };

    // Luminance (with or without alpha) becomes grey RGB; alpha and further channels are dropped, as
    // Mitsuba's bitmap plugin reduces every image to luminance or RGB.
    const int colorChannels = channels >= 3 ? 3 : 1;
    rgb_.resize(size_t(width_) * size_t(height_) * 3);
    Spectrum sum;
    for (int y = 0; y < height_; ++y)
        for (int x = 0; x < width_; ++x) {
            const float* p = &pixels[(size_t(y) * size_t(width_) + size_t(x)) * size_t(channels)];
            for (int c = 0; c < colorChannels; ++c)
                if (!std::isfinite(p[c]))
                    throw Error(filename + ": pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                                ") is not finite");
            if (only >= 0 && !std::isfinite(p[only]))
                throw Error(filename + ": pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is not finite");
            float* out = &rgb_[(size_t(y) * size_t(width_) + size_t(x)) * 3];
            for (int c = 0; c < 3; ++c)
                out[c] = decode(p[only >= 0 ? only : colorChannels == 3 ? c : 0]);
            sum += texel(x, y);
            maximum_ = max(maximum_, texel(x, y));
        }
    average_ = sum / (double(width_) * double(height_));
    if (lookup_.wrapU == BitmapLookup::Wrap::One || lookup_.wrapV == BitmapLookup::Wrap::One)
        maximum_ = max(maximum_, Spectrum(1.0));
}

Spectrum BitmapTexture::texel(int x, int y) const {
    const float* p = &rgb_[(size_t(y) * size_t(width_) + size_t(x)) * 3];
    return {p[0], p[1], p[2]};
}

Spectrum BitmapTexture::wrappedTexel(double x, double y) const {
    using Wrap = BitmapLookup::Wrap;
    // One axis: the texel index in [0, size), or -1 for outside with zero / one.
    auto wrap = [](double i, int size, Wrap mode) -> int {
        switch (mode) {
        case Wrap::Repeat: {
            const double m = std::fmod(i, double(size));
            return int(m < 0 ? m + size : m);
        }
        case Wrap::Mirror: {
            double m = std::fmod(i, 2.0 * size);
            if (m < 0) m += 2.0 * size;
            return int(m < size ? m : 2.0 * size - m - 1);
        }
        case Wrap::Clamp:
            return int(std::clamp(i, 0.0, double(size - 1)));
        case Wrap::Zero:
        case Wrap::One:
            return i >= 0 && i < size ? int(i) : -1;
        }
        return 0;
    };
    const int xi = wrap(x, width_, lookup_.wrapU), yi = wrap(y, height_, lookup_.wrapV);
    if (xi < 0) return Spectrum(lookup_.wrapU == Wrap::One ? 1.0 : 0.0);
    if (yi < 0) return Spectrum(lookup_.wrapV == Wrap::One ? 1.0 : 0.0);
    return texel(xi, yi);
}

Spectrum BitmapTexture::eval(const Vec2& uv) const {
    const double s = (uv.x * scale_.x + offset_.x) * width_;
    const double t = (uv.y * scale_.y + offset_.y) * height_;
    if (!std::isfinite(s) || !std::isfinite(t)) return Spectrum(0.0); // Mitsuba also answers 0 here
    // Nearest: the texel containing the point (Mitsuba's evalBox at level 0).
    if (lookup_.filter == BitmapLookup::Filter::Nearest) return wrappedTexel(std::floor(s), std::floor(t));
    // Bilinear interpolation between the four nearest texel centres (Mitsuba's evalBilinear).
    const double u = s - 0.5, v = t - 0.5;
    const double x0 = std::floor(u), y0 = std::floor(v);
    const double dx = u - x0, dy = v - y0;
    return wrappedTexel(x0, y0) * ((1 - dx) * (1 - dy)) + wrappedTexel(x0 + 1, y0) * (dx * (1 - dy)) +
           wrappedTexel(x0, y0 + 1) * ((1 - dx) * dy) + wrappedTexel(x0 + 1, y0 + 1) * (dx * dy);
}

} // namespace lt
