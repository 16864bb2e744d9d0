// Textures: a spectrum as a function of surface uv. The closed set of Mitsuba 0.5 textures that the
// classic scenes use: constant values, `bitmap` (any format OpenImageIO reads) and `checkerboard`.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "math/spectrum.h"
#include "math/vec.h"

namespace lt {

class Texture {
public:
    virtual ~Texture() = default;
    [[nodiscard]] virtual Spectrum eval(const Vec2& uv) const = 0;
    // Mean over the texture's domain: used where one number must stand for the texture (albedo
    // estimates in lt-inspect, light power).
    [[nodiscard]] virtual Spectrum average() const = 0;
    // Per-channel maximum over the domain: Mitsuba's energy-conservation check of phong and ward reads it.
    [[nodiscard]] virtual Spectrum maximum() const = 0;
    [[nodiscard]] virtual bool isConstant() const { return false; }
    // One number at uv, where a parameter is a scalar (phong's exponent, ward's alphas): the mean of the
    // channels (Mitsuba's eval(its).average()), and a grey value itself, exactly.
    [[nodiscard]] double scalar(const Vec2& uv) const {
        const Spectrum v = eval(uv);
        return v.r == v.g && v.g == v.b ? v.r : v.average();
    }
    // The gradient of the luminance in uv (a bump map's displacement slope): central differences of eval
    // 1e-4 apart in u and in v, which for a bilinear bitmap is its exact slope away from texel boundaries.
    [[nodiscard]] virtual Vec2 luminanceGradient(const Vec2& uv) const;
};

class ConstantTexture final : public Texture {
public:
    explicit ConstantTexture(const Spectrum& value) : value_(value) {}
    [[nodiscard]] Spectrum eval(const Vec2&) const override { return value_; }
    [[nodiscard]] Spectrum average() const override { return value_; }
    [[nodiscard]] Spectrum maximum() const override { return value_; }
    [[nodiscard]] bool isConstant() const override { return true; }
    [[nodiscard]] Vec2 luminanceGradient(const Vec2&) const override { return {}; }

private:
    Spectrum value_;
};

// Mitsuba's `scale`: a nested texture times a constant (as bump maps scale their displacement).
class ScaledTexture final : public Texture {
public:
    ScaledTexture(std::shared_ptr<const Texture> nested, const Spectrum& scale)
        : nested_(std::move(nested)), scale_(scale) {}
    [[nodiscard]] Spectrum eval(const Vec2& uv) const override { return nested_->eval(uv) * scale_; }
    [[nodiscard]] Spectrum average() const override { return nested_->average() * scale_; }
    // An upper bound where a channel's scale is negative (|scale| times the nested maximum; Texture has no
    // minimum), exact otherwise.
    [[nodiscard]] Spectrum maximum() const override {
        const Spectrum m = nested_->maximum();
        Spectrum out;
        for (int c = 0; c < 3; ++c)
            out[c] = scale_[c] >= 0 ? m[c] * scale_[c] : std::abs(m[c] * scale_[c]);
        return out;
    }
    [[nodiscard]] bool isConstant() const override { return nested_->isConstant(); }

private:
    std::shared_ptr<const Texture> nested_;
    Spectrum scale_;
};

// Mitsuba's `checkerboard` (checkerboard.cpp): with (u', v') = uv * scale + offset, color0 where
// int(2u') + int(2v') is even (truncation toward zero, as Mitsuba: 2x2 checks per unit of uv).
class CheckerboardTexture final : public Texture {
public:
    CheckerboardTexture(const Spectrum& color0, const Spectrum& color1, const Vec2& offset, const Vec2& scale)
        : color0_(color0), color1_(color1), offset_(offset), scale_(scale) {}
    [[nodiscard]] Spectrum eval(const Vec2& uv) const override;
    [[nodiscard]] Spectrum average() const override { return (color0_ + color1_) * 0.5; }
    [[nodiscard]] Spectrum maximum() const override { return max(color0_, color1_); }

private:
    Spectrum color0_, color1_;
    Vec2 offset_, scale_;
};

// How a bitmap is read between its texels and beyond its edges (Mitsuba 0.6's bitmap: `filterType`,
// `wrapMode`, `wrapModeU`, `wrapModeV`; its mipmap.h evalTexel). Mitsuba's `ewa` and `trilinear` filter over a
// ray differential's footprint; lt has no ray differentials and reads them bilinearly (the pixel filter and
// the samples per pixel do the averaging). Beyond the edges: repeat, mirror (reflected copies), clamp (the
// edge texel), zero or one (a constant).
struct BitmapLookup {
    enum class Filter { Bilinear, Nearest };
    enum class Wrap { Repeat, Mirror, Clamp, Zero, One };
    Filter filter = Filter::Bilinear;
    Wrap wrapU = Wrap::Repeat, wrapV = Wrap::Repeat;
};

// Mitsuba's `bitmap`: an image read through OpenImageIO, looked up as BitmapLookup says. uv
// (0, 0) is the top-left texel as in Mitsuba's MIP map; OBJ's bottom-left origin comes from the OBJ
// loader flipping v (flipTexCoords). LDR 8-bit images are linearized from sRGB unless gamma says otherwise.
// `channel` (Mitsuba's parameter: a channel name such as "r" or "a", any case) makes a grey texture of that
// one channel; alpha is read linearly, as Mitsuba does.
class BitmapTexture final : public Texture {
public:
    // Throws lt::Error naming the file when it cannot be read, holds NaN or Inf, or has no such channel.
    BitmapTexture(const std::string& filename, double gamma, const Vec2& offset, const Vec2& scale,
                  const std::string& channel = "", const BitmapLookup& lookup = {});
    [[nodiscard]] Spectrum eval(const Vec2& uv) const override;
    [[nodiscard]] Spectrum average() const override { return average_; }
    [[nodiscard]] Spectrum maximum() const override { return maximum_; }
    [[nodiscard]] int width() const { return width_; }
    [[nodiscard]] int height() const { return height_; }

private:
    [[nodiscard]] Spectrum texel(int x, int y) const;
    // The texel at integer coordinates anywhere on the plane, by the wrap modes.
    [[nodiscard]] Spectrum wrappedTexel(double x, double y) const;
    int width_ = 0, height_ = 0;
    BitmapLookup lookup_;
    std::vector<float> rgb_;
    Spectrum average_, maximum_;
    Vec2 offset_, scale_;
};

} // namespace lt
