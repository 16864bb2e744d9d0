// Progress snapshots: the schedule, and what the render loop hands to the snapshot callback.
#include <catch2/catch.hpp>

#include "math/error.h"
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
    rs.bdpt.maxDepth = 4;
    rs.snapshots = SnapshotSchedule::parseSamples("1,2,4");
    std::vector<RenderProgress> at;
    std::vector<std::vector<float>> images;
    const RenderStats st = render(*scene, rs, film, {}, nullptr, nullptr, [&](const RenderProgress& p, const SampleFilm& f) {
        at.push_back(p);
        images.push_back(f.develop());
    });
    REQUIRE(at.size() == 3);
    CHECK(st.snapshots == 3);
    for (size_t i = 1; i < at.size(); ++i) {
        CHECK(at[i].wallSeconds >= at[i - 1].wallSeconds);
        CHECK(at[i].samples > at[i - 1].samples);
    }
    CHECK(at[0].passesDone == 1);
    CHECK(at[2].samples == 4u * 16u * 16u);
    CHECK(images.back() == film.develop());
    CHECK(images.front() != images.back());
}
