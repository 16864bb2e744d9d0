// image/error_metrics: every metric against values worked out by hand on 2x2 and 3x1 images, trimming
// and cropping, the rows of a buffer file with snapshots, and one exact message per bad input.
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <limits>

#include "formats/ltfile.h"
#include "image/error_metrics.h"
#include "image/image_io.h"
#include "util/error.h"
#include "test_util.h"

using namespace lt;

namespace {

using Rgb = std::array<float, 3>;

// An image of R, G, B planes from pixels in row-major order.
file::Buffer rgbImage(uint32_t w, uint32_t h, const std::vector<Rgb>& pixels) {
    file::Buffer b;
    b.width = w;
    b.height = h;
    b.channels = {"R", "G", "B"};
    b.planes.assign(3, std::vector<float>(pixels.size()));
    for (size_t p = 0; p < pixels.size(); ++p)
        for (size_t c = 0; c < 3; ++c)
            b.planes[c][p] = pixels[p][c];
    return b;
}

// The 2x2 case. Each pixel exercises one thing:
//   p0 grey reference 1, R off by 1;
//   p1 black reference, R = 0.1: epsilons and SMAPE's 0/0 on G, B;
//   p2 coloured reference (1, 2, 3), B off by 1: tells (mean ref)^2 = 4 from mean(ref^2) = 14/3;
//   p3 exact.
const file::Buffer kRef22 = rgbImage(2, 2, {{1, 1, 1}, {0, 0, 0}, {1, 2, 3}, {2, 2, 2}});
const file::Buffer kImg22 = rgbImage(2, 2, {{2, 1, 1}, {0.1f, 0, 0}, {1, 2, 4}, {2, 2, 2}});

// relMSE terms, sum_c d^2 / (mean_c(ref)^2 + 0.001) ([GDPR] Sec. 4):
//   p0 1 / (1^2 + 0.001);  p1 0.1^2 / (0 + 0.001) = 10;  p2 1 / (2^2 + 0.001);  p3 0.
const double kRelMse22 = (1 / 1.001 + 0.01 / 0.001 + 1 / 4.001 + 0) / 4;

} // namespace

TEST_CASE("relMSE follows the gradient-domain path reusing paper", "[error]") {
    const ErrorReference ref(kRef22, "ref.exr");
    const ImageError e = ref.error(kImg22, "img.lts", {ErrorMetric::RelMSE, 0, {}});
    CHECK(e.value == Approx(kRelMse22).epsilon(1e-6));
    CHECK(e.pixels == 4);
    CHECK(e.trimmed == 0);
    // The denominator is the squared channel mean: with mean(ref^2) = 14/3 on p2 the value would differ.
    const double meanOfSquares = (1 / 1.001 + 10 + 1 / (14.0 / 3 + 0.001)) / 4;
    CHECK(e.value != Approx(meanOfSquares).epsilon(1e-6));

    const auto terms = ref.pixelErrors(kImg22, "img.lts", ErrorMetric::RelMSE);
    REQUIRE(terms.size() == 4);
    CHECK(terms[0] == Approx(1 / 1.001));
    CHECK(terms[1] == Approx(10).epsilon(1e-6)); // 0.1f is not 0.1: (0.1f)^2 / 0.001 = 10.0000003
    CHECK(terms[2] == Approx(1 / 4.001));
    CHECK(terms[3] == 0);
}

TEST_CASE("rRMSE, MSE, MAPE and SMAPE on a 2x2 image", "[error]") {
    const ErrorReference ref(kRef22, "ref.exr");
    auto value = [&](ErrorMetric m) { return ref.error(kImg22, "img.lts", {m, 0, {}}).value; };
    // rRMSE: the square root of relMSE.
    CHECK(value(ErrorMetric::RRMSE) == Approx(std::sqrt(kRelMse22)).epsilon(1e-6));
    // MSE over all 12 values: squared differences 1 (p0 R), 0.01 (p1 R), 1 (p2 B), the rest 0.
    CHECK(value(ErrorMetric::MSE) == Approx((1 + 0.01 + 1) / 12).epsilon(1e-6));
    // MAPE over 12 values, |d| / (|ref| + 0.01): 1 / 1.01 (p0 R), 0.1 / 0.01 = 10 (p1 R), 1 / 3.01 (p2 B).
    CHECK(value(ErrorMetric::MAPE) == Approx((1 / 1.01 + 10 + 1 / 3.01) / 12).epsilon(1e-6));
    // SMAPE over 12 values, 2|d| / (|I| + |ref|): 2 / 3 (p0 R: 2 and 1), 2 (p1 R: 0.1 and 0, the
    // maximum), 2 / 7 (p2 B: 4 and 3); p1 G, B are 0 and 0: 0 by definition, not NaN.
    CHECK(value(ErrorMetric::SMAPE) == Approx((2.0 / 3 + 2 + 2.0 / 7) / 12).epsilon(1e-6));
    // An image equal to its reference has no error in any metric.
    for (auto m : {ErrorMetric::RelMSE, ErrorMetric::RRMSE, ErrorMetric::MSE, ErrorMetric::MAPE, ErrorMetric::SMAPE})
        CHECK(ref.error(kRef22, "ref.exr", {m, 0, {}}).value == 0);
}

TEST_CASE("trimming drops the worst pixels and says how many", "[error]") {
    const ErrorReference ref(kRef22, "ref.exr");
    // 4 pixels, trim 0.25: floor(1) = 1 pixel dropped, the largest term, p1's 10.
    ImageError e = ref.error(kImg22, "img.lts", {ErrorMetric::RelMSE, 0.25, {}});
    CHECK(e.trimmed == 1);
    CHECK(e.pixels == 3);
    CHECK(e.value == Approx((1 / 1.001 + 1 / 4.001 + 0) / 3));
    // trim 0.2: floor(0.8) = 0, nothing dropped (never more than asked).
    e = ref.error(kImg22, "img.lts", {ErrorMetric::RelMSE, 0.2, {}});
    CHECK(e.trimmed == 0);
    CHECK(e.value == Approx(kRelMse22).epsilon(1e-6));
    // rRMSE trims on relMSE's terms, then takes the root.
    e = ref.error(kImg22, "img.lts", {ErrorMetric::RRMSE, 0.5, {}});
    CHECK(e.trimmed == 2);
    CHECK(e.value == Approx(std::sqrt((1 / 4.001 + 0) / 2)));
}

TEST_CASE("crop on a 3x1 image, alone and with trimming", "[error]") {
    // Grey references 1, 2, 4; the image is each plus 1 in every channel, so the relMSE terms are
    // 3 / (1 + 0.001), 3 / (4 + 0.001), 3 / (16 + 0.001) and every MSE term is 1.
    const ErrorReference ref(rgbImage(3, 1, {{1, 1, 1}, {2, 2, 2}, {4, 4, 4}}), "ref.exr");
    const auto img = rgbImage(3, 1, {{2, 2, 2}, {3, 3, 3}, {5, 5, 5}});
    CHECK(ref.error(img, "img", {ErrorMetric::RelMSE, 0, {}}).value ==
          Approx((3 / 1.001 + 3 / 4.001 + 3 / 16.001) / 3));
    ImageError e = ref.error(img, "img", {ErrorMetric::RelMSE, 0, Crop{1, 0, 2, 1}});
    CHECK(e.pixels == 2);
    CHECK(e.value == Approx((3 / 4.001 + 3 / 16.001) / 2));
    CHECK(ref.error(img, "img", {ErrorMetric::MSE, 0, Crop{2, 0, 1, 1}}).value == Approx(1));
    // Crop, then trim within the crop: half of 2 pixels = 1, the larger term 3 / 4.001 goes.
    e = ref.error(img, "img", {ErrorMetric::RelMSE, 0.5, Crop{1, 0, 2, 1}});
    CHECK(e.trimmed == 1);
    CHECK(e.pixels == 1);
    CHECK(e.value == Approx(3 / 16.001));
}

TEST_CASE("scale to the reference: the factor of the means and the error left after it", "[error]") {
    // The image is the reference (1, 2, 4 grey) times 2 plus (0, 0, 0.5) at the last pixel: over the whole
    // image the sums are 21 and 42.5, so the scale is 21 / 42.5; over the crop of the first two pixels it
    // is exactly 1/2, and the rescaled image there equals the reference.
    const ErrorReference ref(rgbImage(3, 1, {{1, 1, 1}, {2, 2, 2}, {4, 4, 4}}), "ref.exr");
    const auto img = rgbImage(3, 1, {{2, 2, 2}, {4, 4, 4}, {8, 8, 8.5f}});
    CHECK(ref.scaleToReference(img, "img", {}) == Approx(21 / 42.5));
    CHECK(ref.scaleToReference(img, "img", Crop{0, 0, 2, 1}) == Approx(0.5));
    CHECK(std::isnan(ref.scaleToReference(rgbImage(3, 1, {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}), "black", {})));
}

TEST_CASE("a NaN in the image is the worst pixel: trimmed first, else it shows", "[error]") {
    const ErrorReference ref(rgbImage(3, 1, {{1, 1, 1}, {2, 2, 2}, {4, 4, 4}}), "ref.exr");
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const auto img = rgbImage(3, 1, {{2, 2, 2}, {nan, 3, 3}, {5, 5, 5}});
    CHECK(std::isnan(ref.error(img, "img", {ErrorMetric::RelMSE, 0, {}}).value));
    // 3 pixels, trim 0.34: floor(1.02) = 1, the NaN pixel.
    const ImageError e = ref.error(img, "img", {ErrorMetric::RelMSE, 0.34, {}});
    CHECK(e.trimmed == 1);
    CHECK(e.value == Approx((3 / 1.001 + 3 / 16.001) / 2));
}

TEST_CASE("error metrics reject bad inputs with one clear message", "[error]") {
    const ErrorReference ref(kRef22, "ref.exr");
    CHECK(test::errorOf([&] {
              (void)ref.error(rgbImage(3, 1, {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}), "img.lts", {});
          }) == "cannot compare img.lts with ref.exr: sizes differ (3x1 and 2x2)");
    file::Buffer noG = kRef22;
    noG.channels = {"R", "X", "B"};
    CHECK(test::errorOf([&] { ErrorReference r(noG, "ref.exr"); }) ==
          "ref.exr: no channel G (the error is measured on channels R, G, B; it has R, X, B)");
    CHECK(test::errorOf([&] { (void)ref.error(noG, "img.lts", {}); }) ==
          "img.lts: no channel G (the error is measured on channels R, G, B; it has R, X, B)");

    // A film with further planes names its image primal.R/G/B: measured as R, G, B.
    file::Buffer planes = kRef22;
    planes.channels = {"primal.R", "primal.G", "primal.B"};
    planes.planes[1][0] += 1;
    planes.channels.push_back("dx.R");
    planes.planes.push_back(std::vector<float>(4, 100.0f));
    file::Buffer same = kRef22;
    same.planes[1][0] += 1;
    CHECK(ref.error(planes, "grad.lts", {}).value == ref.error(same, "img.lts", {}).value);
    CHECK(ref.error(planes, "grad.lts", {}).value > 0);
    planes.channels[1] = "primal.X";
    CHECK(test::errorOf([&] { (void)ref.error(planes, "grad.lts", {}); }).find("grad.lts: no channel primal.G") == 0);

    // The first bad pixel in row-major order is named: the Inf at (1, 0) before the NaN at (1, 1).
    file::Buffer bad = kRef22;
    bad.planes[2][3] = std::numeric_limits<float>::quiet_NaN(); // B at (1, 1)
    CHECK(test::errorOf([&] { ErrorReference r(bad, "ref.exr"); }) ==
          "ref.exr: the reference has a NaN at pixel (1, 1) in channel B");
    bad.planes[1][1] = std::numeric_limits<float>::infinity(); // G at (1, 0)
    CHECK(test::errorOf([&] { ErrorReference r(bad, "ref.exr"); }) ==
          "ref.exr: the reference has an infinite value at pixel (1, 0) in channel G");

    CHECK(test::errorOf([&] {
              (void)ref.error(kImg22, "img", {ErrorMetric::RelMSE, 0, Crop{1, 1, 2, 1}});
          }) == "crop 1,1,2,1 does not fit the 2x2 image");
    CHECK(test::errorOf([&] {
              (void)ref.error(kImg22, "img", {ErrorMetric::RelMSE, 1, {}});
          }) == "trim fraction 1.000000 is outside [0, 1)");
    CHECK(test::errorOf([] { (void)parseCrop("1,2,3"); }) ==
          "crop '1,2,3' is not X,Y,W,H (whole numbers, W and H > 0)");
    CHECK(test::errorOf([] { (void)parseCrop("1,2,0,4"); }) ==
          "crop '1,2,0,4' is not X,Y,W,H (whole numbers, W and H > 0)");
    CHECK(test::errorOf([] { (void)parseErrorMetric("psnr"); }) ==
          "unknown error metric 'psnr' (relmse, rrmse, mse, mape or smape)");
    const Crop c = parseCrop("1,2,3,4");
    CHECK((c.x == 1 && c.y == 2 && c.width == 3 && c.height == 4));
    CHECK(errorMetricName(parseErrorMetric("rrmse")) == "rRMSE");
}

TEST_CASE("a buffer file gives one row per snapshot, then its final buffer", "[error]") {
    test::TempDir dir;
    const ErrorReference ref(kRef22, "ref.exr");
    const std::string path = dir.file("run.lts");
    {
        file::Writer w(path, file::FileKind::Buffer, nlohmann::json::object());
        w.writeSnapshot({1.0, 3.5, 4, 0.01, kImg22});
        w.writeSnapshot({2.0, 7.5, 8, 0.02, kRef22});
        w.writeBuffer(kImg22);
        w.writeStats({"run", {"value"}, {"samples", "wall_seconds", "cpu_seconds"}, {{16}, {2.5}, {9}}});
        w.finish();
    }
    const ErrorCurve curve = measureErrorCurve(path, ref, {});
    REQUIRE(curve.rows.size() == 3);
    CHECK(curve.rows[0].label == "SNAP 1 of 2");
    CHECK(curve.rows[0].wallSeconds == 1.0);
    CHECK(curve.rows[0].cpuSeconds == 3.5);
    CHECK(curve.rows[0].samples == 4u);
    CHECK(curve.rows[0].error.value == Approx(kRelMse22).epsilon(1e-6));
    // 1 / (error x time)
    CHECK(*curve.rows[0].efficiency() == Approx(1 / (kRelMse22 * 1.0)).epsilon(1e-6));
    // Sums of R + G + B: reference 15, image 17.1.
    CHECK(curve.rows[0].scale == Approx(15 / 17.1));
    CHECK(curve.rows[1].label == "SNAP 2 of 2");
    CHECK(curve.rows[1].error.value == 0);
    CHECK(curve.rows[1].scale == Approx(1));
    CHECK(curve.rows[1].rescaledError.value == 0);
    // The final buffer's time and samples come from the STAT table "run".
    CHECK(curve.rows[2].label == "BUFR");
    CHECK(curve.rows[2].wallSeconds == 2.5);
    CHECK(curve.rows[2].cpuSeconds == 9.0);
    CHECK(curve.rows[2].samples == 16u);
    CHECK(curve.rows[2].error.value == Approx(kRelMse22).epsilon(1e-6));
    // The map is the final buffer's, not the last snapshot's (which had no error).
    REQUIRE(curve.finalErrors.size() == 4);
    CHECK(curve.finalErrors[1] == Approx(10).epsilon(1e-6));

    // An EXR: one row, no time.
    const std::string exr = dir.file("img.exr");
    writeExr(exr, kImg22, nlohmann::json::object());
    const ErrorCurve e = measureErrorCurve(exr, ref, {});
    REQUIRE(e.rows.size() == 1);
    CHECK(e.rows[0].label == "EXR");
    CHECK(!e.rows[0].wallSeconds);
    CHECK(!e.rows[0].efficiency());
    CHECK(e.rows[0].error.value == Approx(kRelMse22).epsilon(1e-6));
}
