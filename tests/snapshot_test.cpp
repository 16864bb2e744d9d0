// Progress snapshots: the schedule, and what the render loop hands to the snapshot callback.
#include <catch2/catch.hpp>

#include <cmath>

#include "image/error_metrics.h"
#include "util/error.h"
#include "sampling/path_tracer.h"
#include "sampling/render.h"
#include "scene/scene.h"
#include "test_util.h"

using namespace lt;

TEST_CASE("snapshot schedules: doubling, lists of times, sample counts", "[snapshots]") {
    auto d = SnapshotSchedule::parseTimes("doubling");
    CHECK_FALSE(d.due(0.5, 0));
    CHECK(d.due(1.0, 0));
    CHECK_FALSE(d.due(1.5, 0));
    CHECK(d.due(2.1, 0));
    CHECK(d.due(9, 0));      // covers 4 and 8 at once: one snapshot for a slow pass
    CHECK_FALSE(d.due(15, 0));
    CHECK(d.due(16, 0));
    auto s = SnapshotSchedule::parseTimes("doubling:0.25");
    CHECK(s.due(0.25, 0));
    CHECK_FALSE(s.due(0.4, 0));
    auto t = SnapshotSchedule::parseTimes("5,10,30");
    CHECK_FALSE(t.due(4, 100));
    CHECK(t.due(5, 0));
    CHECK(t.due(31, 0));
    CHECK_FALSE(t.due(100, 0));
    auto n = SnapshotSchedule::parseSamples("1,2,4");
    CHECK(n.due(1000, 1));
    CHECK_FALSE(n.due(1000, 1));
    CHECK(n.due(0, 4));
    CHECK_FALSE(SnapshotSchedule().enabled());
    CHECK_THROWS_WITH(SnapshotSchedule::parseTimes("5,3"), "snapshot times must increase, got '5,3'");
    CHECK_THROWS_WITH(SnapshotSchedule::parseTimes("doubling:x"),
                      "snapshot start must be positive numbers separated by commas, got 'x'");
    CHECK_THROWS_WITH(SnapshotSchedule::parseSamples("1,,2"),
                      "snapshot sample counts must be positive numbers separated by commas, got '1,,2'");
    CHECK_THROWS_AS(SnapshotSchedule::parseTimes("-1"), Error);
}

TEST_CASE("snapshots: increasing times, and the last one equals the final image", "[snapshots]") {
    const auto scene = loadScene(test::shippedScene("cornell-spheres"), {{"res", "16"}});
    SampleFilm film(scene->camera);
    RenderSettings rs;
    rs.spp = 4;
    rs.paths.maxDepth = 4;
    rs.snapshots = SnapshotSchedule::parseSamples("1,2,4");
    std::vector<RunProgress> at;
    std::vector<std::vector<std::vector<float>>> images;
    const RenderStats st = render(*scene, Bdpt(*scene, rs.paths), rs, film,
                                  RunControl(0, [&](const RunProgress& p, const file::Buffer& image) {
                                      at.push_back(p);
                                      images.push_back(image.planes);
                                  }));
    REQUIRE(at.size() == 3);
    CHECK(st.snapshots == 3);
    for (size_t i = 1; i < at.size(); ++i) {
        CHECK(at[i].wallSeconds >= at[i - 1].wallSeconds);
        CHECK(at[i].samples > at[i - 1].samples);
    }
    CHECK(at[0].passesDone == 1);
    CHECK(at[2].samples == 4u * 16u * 16u);
    CHECK(images.back() == film.toBuffer().planes);
    CHECK(images.front() != images.back());
}

TEST_CASE("the error of path tracing falls as 1/samples: log-log slope near -1", "[snapshots]") {
    // A furnace box (every wall emits 1 and reflects 0.5, maxDepth 3) has the exact value 1.75 in every
    // pixel: the reference is analytic. relMSE of an unbiased pixel average is variance / n, so against
    // samples (and time) it falls with slope -1.
    test::TempDir dir;
    const std::string xml = dir.write("box.xml", R"(<scene version="0.5.0">
  <integrator type="path"><integer name="maxDepth" value="3"/></integrator>
  <sensor type="perspective"><float name="fov" value="60"/>
    <transform name="toWorld"><lookat origin="0.1,0.2,0.3" target="1,0.5,-2" up="0,1,0"/></transform>
    <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="24"/><rfilter type="box"/></film>
  </sensor>
  <shape type="cube"><boolean name="flipNormals" value="true"/>
    <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf>
    <emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>
</scene>)");
    const auto scene = loadScene(xml);
    file::Buffer ref;
    ref.width = ref.height = 24;
    ref.channels = {"R", "G", "B"};
    ref.planes.assign(3, std::vector<float>(24 * 24, 1.75f));
    const ErrorReference reference(ref, "analytic");
    SampleFilm film(scene->camera);
    RenderSettings rs;
    rs.spp = 256;
    rs.paths.maxDepth = 3;
    rs.snapshots = SnapshotSchedule::parseSamples("4,8,16,32,64,128,256");
    std::vector<double> logN, logE;
    (void)render(*scene, PathTracer(*scene, rs.paths), rs, film,
                 RunControl(0, [&](const RunProgress& p, const file::Buffer& image) {
                     logN.push_back(std::log(double(p.passesDone)));
                     logE.push_back(std::log(reference.error(image, "render", ErrorOptions{}).value));
                 }));
    REQUIRE(logN.size() == 7);
    // Least-squares slope. Each relMSE is a mean over 576 pixels: relative spread ~ sqrt(2/576) = 6 %,
    // i.e. 0.06 in log; over a log range of ln(64) = 4.2 the slope's error is a few hundredths. 0.15
    // bounds it with a wide margin and still rejects a biased estimator (its error flattens, slope -> 0).
    double mx = 0, my = 0;
    for (size_t i = 0; i < logN.size(); ++i) mx += logN[i] / 7, my += logE[i] / 7;
    double sxy = 0, sxx = 0;
    for (size_t i = 0; i < logN.size(); ++i) sxy += (logN[i] - mx) * (logE[i] - my), sxx += (logN[i] - mx) * (logN[i] - mx);
    const double slope = sxy / sxx;
    CHECK(std::abs(slope + 1) < 0.15);
}
