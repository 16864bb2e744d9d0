// Textures: Mitsuba 0.5/0.6 checkerboard and bitmap semantics (uv transform, orientation, bilinear and nearest
// lookups, the wrap modes, sRGB / gamma decoding) and the error paths of BitmapTexture.
#include <OpenImageIO/imageio.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <unistd.h>
#include <vector>

#include "util/error.h"
#include "test_util.h"
#include "texture/texture.h"

namespace fs = std::filesystem;
using namespace lt;

namespace {

using test::TempDir;

// Writes an image through OpenImageIO; `pixels` are row-major from the top row, channels interleaved.
template <class T> std::string writeImage(const fs::path &path, int width, int height, int channels,
                                          OIIO::TypeDesc type, const std::vector<T> &pixels) {
    auto out = OIIO::ImageOutput::create(path.string());
    REQUIRE(out);
    OIIO::ImageSpec spec(width, height, channels, type);
    spec.attribute("oiio:UnassociatedAlpha", 1); // write colors as given, not divided by alpha
    REQUIRE(out->open(path.string(), spec));
    REQUIRE(out->write_image(OIIO::TypeDescFromC<T>::value(), pixels.data()));
    REQUIRE(out->close());
    return path.string();
}

double srgbToLinear(double v) {
    return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

void checkSpectrum(const Spectrum &got, const Spectrum &want, double eps = 1e-6) {
    INFO("got (" << got.r << ", " << got.g << ", " << got.b << "), want (" << want.r << ", " << want.g << ", " << want.b
                 << ")");
    CHECK(std::abs(got.r - want.r) <= eps);
    CHECK(std::abs(got.g - want.g) <= eps);
    CHECK(std::abs(got.b - want.b) <= eps);
}

const Vec2 kNoOffset(0, 0), kUnitScale(1, 1);

} // namespace

TEST_CASE("checkerboard: Mitsuba 0.5's 2x2 checks per unit uv, with its truncation at zero", "[texture]") {
    const Spectrum c0(0.4), c1(0.2);
    const CheckerboardTexture board(c0, c1, kNoOffset, kUnitScale);
    // color0 where int(2u) + int(2v) is even (checkerboard.cpp).
    CHECK(board.eval({0.1, 0.1}) == c0);
    CHECK(board.eval({0.6, 0.1}) == c1);
    CHECK(board.eval({0.1, 0.6}) == c1);
    CHECK(board.eval({0.6, 0.6}) == c0);
    CHECK(board.eval({1.1, 0.1}) == c0);
    // int() truncates toward zero: (-0.5, 0.5) is one check twice as wide as the others.
    CHECK(board.eval({-0.2, 0.1}) == c0);
    CHECK(board.eval({-0.6, 0.1}) == c1);
    CHECK(board.eval({-1.1, 0.1}) == c0);
    checkSpectrum(board.average(), Spectrum(0.3));

    // uv' = uv * scale + offset (Texture2D::eval): scale 4 puts (0.2, 0) in check int(1.6) = 1.
    const CheckerboardTexture scaled(c0, c1, Vec2(0, 0), Vec2(4, 1));
    CHECK(scaled.eval({0.2, 0.1}) == c1);
    const CheckerboardTexture shifted(c0, c1, Vec2(0.5, 0), Vec2(1, 1));
    CHECK(shifted.eval({0.1, 0.1}) == c1);
}

TEST_CASE("bitmap: orientation, bilinear filtering, repeat wrapping and the uv transform", "[texture]") {
    TempDir dir;
    // 2x2 float image, linear: top row red, green; bottom row blue, white*2.
    const std::vector<float> pixels = {1, 0, 0, 0, 1, 0, 0, 0, 1, 2, 2, 2};
    const std::string file = writeImage(dir.path / "quad.exr", 2, 2, 3, OIIO::TypeDesc::FLOAT, pixels);
    const BitmapTexture tex(file, 0, kNoOffset, kUnitScale);
    CHECK(tex.width() == 2);
    CHECK(tex.height() == 2);
    // Mitsuba's MIP map: texel (u*w - 0.5, v*h - 0.5), row 0 = the image's first (top) row.
    checkSpectrum(tex.eval({0.25, 0.25}), Spectrum(1, 0, 0));
    checkSpectrum(tex.eval({0.75, 0.25}), Spectrum(0, 1, 0));
    checkSpectrum(tex.eval({0.25, 0.75}), Spectrum(0, 0, 1));
    checkSpectrum(tex.eval({0.75, 0.75}), Spectrum(2, 2, 2));
    // Halfway between the two top texels, and across the left edge (wraps to the right column).
    checkSpectrum(tex.eval({0.5, 0.25}), Spectrum(0.5, 0.5, 0));
    checkSpectrum(tex.eval({0.0, 0.25}), Spectrum(0.5, 0.5, 0));
    // The centre mixes all four equally.
    checkSpectrum(tex.eval({0.5, 0.5}), Spectrum(0.75, 0.75, 0.75));
    // Repeat wrapping, also for negative uv.
    checkSpectrum(tex.eval({1.25, -0.75}), Spectrum(1, 0, 0));
    checkSpectrum(tex.eval({-3.25, 7.75}), Spectrum(2, 2, 2));
    checkSpectrum(tex.average(), Spectrum(0.75, 0.75, 0.75));

    // uv' = uv * scale + offset.
    const BitmapTexture scaled(file, 0, Vec2(0.5, 0), Vec2(2, 2));
    checkSpectrum(scaled.eval({0.125, 0.125}), Spectrum(0, 1, 0)); // uv' = (0.75, 0.25)
}

TEST_CASE("bitmap: Mitsuba 0.6's wrap modes per axis and the nearest filter", "[texture]") {
    TempDir dir;
    // 3x1 grey image 1, 2, 4 (one row: v wraps trivially except for zero and one).
    const std::vector<float> pixels = {1, 1, 1, 2, 2, 2, 4, 4, 4};
    const std::string file = writeImage(dir.path / "row.exr", 3, 1, 3, OIIO::TypeDesc::FLOAT, pixels);
    using Wrap = BitmapLookup::Wrap;
    auto at = [&](Wrap u, Wrap v, BitmapLookup::Filter f, double x, double y = 0.5) {
        return BitmapTexture(file, 0, kNoOffset, kUnitScale, "", {f, u, v}).eval({x, y}).g;
    };
    const auto Nearest = BitmapLookup::Filter::Nearest, Bilinear = BitmapLookup::Filter::Bilinear;
    // Texel centres at u = 1/6, 1/2, 5/6; u = 7/6 is the centre of the texel after the last one.
    const double next = 7.0 / 6, before = -1.0 / 6;
    CHECK(at(Wrap::Repeat, Wrap::Repeat, Nearest, next) == 1); // the first texel again
    CHECK(at(Wrap::Mirror, Wrap::Repeat, Nearest, next) == 4); // the last texel, reflected
    CHECK(at(Wrap::Mirror, Wrap::Repeat, Nearest, 9.0 / 6) == 2);
    CHECK(at(Wrap::Mirror, Wrap::Repeat, Nearest, 11.0 / 6) == 1);
    CHECK(at(Wrap::Mirror, Wrap::Repeat, Nearest, before) == 1);
    CHECK(at(Wrap::Clamp, Wrap::Repeat, Nearest, 5.0) == 4);
    CHECK(at(Wrap::Clamp, Wrap::Repeat, Nearest, -5.0) == 1);
    CHECK(at(Wrap::Zero, Wrap::Repeat, Nearest, next) == 0);
    CHECK(at(Wrap::One, Wrap::Repeat, Nearest, before) == 1);
    CHECK(at(Wrap::One, Wrap::Repeat, Nearest, next) == 1);
    // Per axis: v beyond the image with zero / one while u repeats.
    CHECK(at(Wrap::Repeat, Wrap::Zero, Nearest, 0.5, 1.5) == 0);
    CHECK(at(Wrap::Repeat, Wrap::One, Nearest, 0.5, -0.5) == 1);
    CHECK(at(Wrap::Repeat, Wrap::Repeat, Nearest, 0.5, 1.5) == 2);
    // Nearest holds a texel's value up to its edges; bilinear blends toward the neighbour.
    CHECK(at(Wrap::Repeat, Wrap::Repeat, Nearest, 0.66) == 2);
    CHECK(at(Wrap::Repeat, Wrap::Repeat, Bilinear, 0.66) == Approx(2 + 2 * (0.66 * 3 - 1.5)));
    // Bilinear at the last texel's right edge: half of it and half of what lies beyond.
    CHECK(at(Wrap::Repeat, Wrap::Repeat, Bilinear, 1.0) == Approx(2.5)); // (4 + 1) / 2
    CHECK(at(Wrap::Mirror, Wrap::Repeat, Bilinear, 1.0) == Approx(4));   // (4 + 4) / 2
    CHECK(at(Wrap::Clamp, Wrap::Repeat, Bilinear, 1.0) == Approx(4));
    CHECK(at(Wrap::Zero, Wrap::Repeat, Bilinear, 1.0) == Approx(2));  // (4 + 0) / 2
    CHECK(at(Wrap::One, Wrap::Repeat, Bilinear, 1.0) == Approx(2.5)); // (4 + 1) / 2
    // The texture's maximum covers the constant 1 of `one`.
    CHECK(BitmapTexture(file, 0, kNoOffset, kUnitScale, "", {Nearest, Wrap::One, Wrap::Repeat}).maximum().g == 4);
}

TEST_CASE("bitmap: 8-bit images are decoded from sRGB unless gamma says otherwise", "[texture]") {
    TempDir dir;
    // One RGBA pixel row: (128, 64, 255, alpha 10), (0, 255, 32, alpha 255). Alpha is ignored.
    const std::vector<unsigned char> rgba = {128, 64, 255, 10, 0, 255, 32, 255};
    const std::string png = writeImage(dir.path / "row.png", 2, 1, 4, OIIO::TypeDesc::UINT8, rgba);
    auto value = [](int byte) { return byte / 255.0; };
    const double eps = 1e-5;

    const BitmapTexture automatic(png, 0, kNoOffset, kUnitScale);
    checkSpectrum(automatic.eval({0.25, 0.5}), Spectrum(srgbToLinear(value(128)), srgbToLinear(value(64)), 1.0), eps);
    const BitmapTexture srgb(png, -1, kNoOffset, kUnitScale);
    checkSpectrum(srgb.eval({0.75, 0.5}), Spectrum(0, 1, srgbToLinear(value(32))), eps);
    const BitmapTexture linear(png, 1, kNoOffset, kUnitScale);
    checkSpectrum(linear.eval({0.25, 0.5}), Spectrum(value(128), value(64), 1), eps);
    const BitmapTexture gamma22(png, 2.2, kNoOffset, kUnitScale);
    checkSpectrum(gamma22.eval({0.25, 0.5}), Spectrum(std::pow(value(128), 2.2), std::pow(value(64), 2.2), 1), eps);

    // Greyscale becomes grey RGB.
    const std::vector<unsigned char> grey = {200};
    const std::string greyPng = writeImage(dir.path / "grey.png", 1, 1, 1, OIIO::TypeDesc::UINT8, grey);
    checkSpectrum(BitmapTexture(greyPng, 0, kNoOffset, kUnitScale).eval({0.3, 0.7}), Spectrum(srgbToLinear(value(200))),
                  eps);

    // Float images are linear by default: values above 1 survive.
    const std::vector<float> hdr = {4.5f, 0.25f, 0.0f};
    const std::string exr = writeImage(dir.path / "bright.exr", 1, 1, 3, OIIO::TypeDesc::HALF, hdr);
    checkSpectrum(BitmapTexture(exr, 0, kNoOffset, kUnitScale).eval({0.5, 0.5}), Spectrum(4.5, 0.25, 0));

    CHECK(test::errorOf([&] { BitmapTexture(png, -2, kNoOffset, kUnitScale); }) ==
          png + ": gamma -2.000000 is not supported (use -1 for sRGB, 0 for automatic or a positive exponent)");
}

TEST_CASE("bitmap: one channel as a grey texture, alpha read linearly (Mitsuba's channel)", "[texture]") {
    TempDir dir;
    const std::vector<unsigned char> rgba = {128, 64, 255, 10};
    const std::string png = writeImage(dir.path / "rgba.png", 1, 1, 4, OIIO::TypeDesc::UINT8, rgba);
    const double eps = 1e-5;
    // Colour channels are decoded as the image is (sRGB here); alpha is a fraction as stored.
    checkSpectrum(BitmapTexture(png, 0, kNoOffset, kUnitScale, "g").eval({0.5, 0.5}),
                  Spectrum(srgbToLinear(64 / 255.0)), eps);
    checkSpectrum(BitmapTexture(png, 0, kNoOffset, kUnitScale, "A").eval({0.5, 0.5}), Spectrum(10 / 255.0), eps);
    CHECK(test::errorOf([&] { BitmapTexture(png, 0, kNoOffset, kUnitScale, "z"); }) ==
          png + ": no channel 'z' (it has r, g, b, a)");
    // A one-channel image's channel is "l" to Mitsuba ("y" to OpenImageIO).
    const std::vector<unsigned char> grey = {200};
    const std::string greyPng = writeImage(dir.path / "grey.png", 1, 1, 1, OIIO::TypeDesc::UINT8, grey);
    checkSpectrum(BitmapTexture(greyPng, 0, kNoOffset, kUnitScale, "l").eval({0.5, 0.5}),
                  Spectrum(srgbToLinear(200 / 255.0)), eps);
}

TEST_CASE("bitmap: unreadable files and non-finite pixels are errors naming the file", "[texture]") {
    TempDir dir;
    const std::string missing = (dir.path / "missing.png").string();
    const std::string missingError = test::errorOf([&] { BitmapTexture(missing, 0, kNoOffset, kUnitScale); });
    CHECK_THAT(missingError, Catch::StartsWith(missing + ": cannot read image (") && Catch::EndsWith(")"));
    CHECK(missingError.find('\n') == std::string::npos);

    const std::string garbage = (dir.path / "garbage.png").string();
    std::ofstream(garbage) << "this is not a PNG file";
    CHECK_THAT(test::errorOf([&] { BitmapTexture(garbage, 0, kNoOffset, kUnitScale); }),
               Catch::StartsWith(garbage + ": cannot read image (") && Catch::EndsWith(")"));

    const float nan = std::numeric_limits<float>::quiet_NaN();
    const std::vector<float> pixels = {0, 0, 0, 1, 1, 1, 0.5f, nan, 0.5f, 0, 0, 0};
    const std::string exr = writeImage(dir.path / "nan.exr", 2, 2, 3, OIIO::TypeDesc::FLOAT, pixels);
    CHECK(test::errorOf([&] { BitmapTexture(exr, 0, kNoOffset, kUnitScale); }) == exr + ": pixel (0, 1) is not finite");

    const std::vector<float> infinite = {0, std::numeric_limits<float>::infinity(), 0};
    const std::string infExr = writeImage(dir.path / "inf.exr", 1, 1, 3, OIIO::TypeDesc::FLOAT, infinite);
    CHECK(test::errorOf([&] { BitmapTexture(infExr, 0, kNoOffset, kUnitScale); }) == infExr + ": pixel (0, 0) is not finite");
}
