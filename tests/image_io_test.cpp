// image/image_io and image/buffer_merge: EXR round trip (names, exact floats, INFO metadata), EXR files
// written by other software, the sRGB PNG preview against the sRGB formula, merging by weights exactly,
// one clear error per mismatch, no output under the final name when a write fails, and EXR headers checked
// before OpenEXR allocates what they declare.
#include <OpenImageIO/imageio.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>

#include "image/buffer_merge.h"
#include "image/image_io.h"
#include "texture/exr_header.h"
#include "util/error.h"
#include "test_util.h"

namespace fs = std::filesystem;
using namespace lt;

namespace {

file::Buffer makeBuffer(uint32_t w, uint32_t h, std::vector<std::string> channels, double weight, float base) {
    file::Buffer b;
    b.width = w;
    b.height = h;
    b.channels = std::move(channels);
    b.weight = weight;
    for (size_t c = 0; c < b.channels.size(); ++c) {
        auto& plane = b.planes.emplace_back(size_t(w) * h);
        for (size_t p = 0; p < plane.size(); ++p)
            plane[p] = base + float(c * 100 + p);
    }
    return b;
}

const std::vector<float>& plane(const file::Buffer& b, const std::string& name) {
    const auto it = std::find(b.channels.begin(), b.channels.end(), name);
    REQUIRE(it != b.channels.end());
    return b.planes[size_t(it - b.channels.begin())];
}

// Files in `dir` other than `except`: a failed write must leave no temporary file behind.
std::vector<std::string> leftovers(const fs::path& dir, const std::string& except = "") {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.path().filename() != except) names.push_back(e.path().filename().string());
    return names;
}

} // namespace

TEST_CASE("EXR round trip keeps channel names, exact floats and INFO", "[image]") {
    test::TempDir dir;
    // Layers out of alphabetical order and the beauty last, so the writer has to put R, G, B first.
    file::Buffer b = makeBuffer(5, 3, {"var.R", "dx.R", "dx.G", "dx.B", "B", "G", "R", "Y"}, 1, 0.25f);
    // Values a lossy or converting writer would change.
    b.planes[0][0] = -0.0f;
    b.planes[1][1] = std::numeric_limits<float>::denorm_min();
    b.planes[2][2] = std::numeric_limits<float>::max();
    b.planes[3][3] = 1.0f / 3.0f;
    b.planes[6][4] = std::numeric_limits<float>::infinity();
    const nlohmann::json info = {{"producer", "lt-seed"},
                                 {"parameters", {{"spp", 16}}},
                                 {"scene", {{"path", "s\xc3\xa9ne.xml"}, {"hash", "0123456789abcdef"}}}};
    const std::string path = dir.file("out.exr");
    writeExr(path, b, info);
    CHECK(isExrFile(path));

    const file::Buffer r = readExr(path);
    CHECK(r.width == 5);
    CHECK(r.height == 3);
    CHECK(r.weight == 1);
    REQUIRE(r.channels.size() == b.channels.size());
    CHECK(std::vector<std::string>(r.channels.begin(), r.channels.begin() + 3) ==
          std::vector<std::string>{"R", "G", "B"});
    for (size_t c = 0; c < b.channels.size(); ++c) {
        CAPTURE(b.channels[c]);
        const auto& got = plane(r, b.channels[c]);
        for (size_t p = 0; p < got.size(); ++p)
            CHECK(std::bit_cast<uint32_t>(got[p]) == std::bit_cast<uint32_t>(b.planes[c][p]));
    }

    auto in = OIIO::ImageInput::open(path);
    REQUIRE(in);
    const OIIO::ImageSpec& spec = in->spec();
    CHECK(nlohmann::json::parse(spec.get_string_attribute("lt:info")) == info);
    CHECK(spec.get_string_attribute("lt:producer") == "lt-seed");
    CHECK(spec.get_string_attribute("lt:scene") == "s\xc3\xa9ne.xml");
    CHECK(spec.get_string_attribute("lt:scene_hash") == "0123456789abcdef");
}

TEST_CASE("an EXR written by other software reads as a buffer (half floats, layers)", "[image]") {
    test::TempDir dir;
    const std::string path = dir.file("other.exr");
    OIIO::ImageSpec spec(2, 2, 4, OIIO::TypeDesc::HALF);
    spec.channelnames = {"R", "G", "B", "diffuse.R"};
    spec.alpha_channel = -1;
    // Values exact in half precision.
    const std::vector<float> data = {0.5f, 1, 2, 4, 0.25f, 8, 16, -1, 0, 0.125f, 3, 5, 6, 7, 9, 10};
    auto out = OIIO::ImageOutput::create(path);
    REQUIRE(out);
    REQUIRE(out->open(path, spec));
    REQUIRE(out->write_image(OIIO::TypeDesc::FLOAT, data.data()));
    REQUIRE(out->close());

    const file::Buffer b = readExr(path);
    CHECK(b.width == 2);
    CHECK(b.height == 2);
    CHECK(plane(b, "R") == std::vector<float>{0.5f, 0.25f, 0, 6});
    CHECK(plane(b, "diffuse.R") == std::vector<float>{4, -1, 5, 10});
    CHECK(b.combine == "weighted-mean");
    CHECK(b.weight == 1);
    CHECK_THAT(test::errorOf([&] { (void)readExr(dir.file("missing.exr")); }), Catch::Contains("missing.exr"));
    const std::string notExr = dir.write("x.exr", "not an image");
    CHECK_THAT(test::errorOf([&] { (void)readExr(notExr); }), Catch::Contains(notExr));
}

TEST_CASE("PNG preview: sRGB of the exposed linear value, clamped, NaN-safe", "[image]") {
    test::TempDir dir;
    file::Buffer b = makeBuffer(4, 1, {"R", "G", "B"}, 1, 0);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    // Pixels: 0.5 grey; 0.25 grey; (NaN, -1, 2); (1, 0.0031308 (end of the linear segment), 0).
    b.planes[0] = {0.5f, 0.25f, nan, 1};
    b.planes[1] = {0.5f, 0.25f, -1, 0.0031308f};
    b.planes[2] = {0.5f, 0.25f, 2, 0};
    auto read = [&](const std::string& path) {
        auto in = OIIO::ImageInput::open(path);
        REQUIRE(in);
        CHECK(std::string(in->format_name()) == "png");
        CHECK(in->spec().width == 4);
        CHECK(in->spec().nchannels == 3);
        std::vector<uint8_t> px(12);
        REQUIRE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, px.data()));
        return px;
    };
    // sRGB(0.5) = 1.055 * 0.5^(1/2.4) - 0.055 = 0.73536, * 255 = 187.5 -> 188; sRGB(0.25) = 0.53709 -> 137;
    // 0.0031308 * 12.92 * 255 = 10.3 -> 10.
    writePng(dir.file("a.png"), b, 0);
    CHECK(read(dir.file("a.png")) == std::vector<uint8_t>{188, 188, 188, 137, 137, 137, 0, 0, 255, 255, 10, 0});
    // +1 EV doubles: 0.25 shows as 0.5 did.
    writePng(dir.file("b.png"), b, 1);
    const auto exposed = read(dir.file("b.png"));
    CHECK(std::vector<uint8_t>(exposed.begin() + 3, exposed.begin() + 6) == std::vector<uint8_t>{188, 188, 188});
    // No beauty channels: a clear error, no file.
    const file::Buffer grad = makeBuffer(2, 2, {"dx.X"}, 1, 0);
    CHECK_THAT(test::errorOf([&] { writePng(dir.file("c.png"), grad, 0); }), Catch::Contains("no R, G, B"));
    CHECK(!fs::exists(dir.file("c.png")));
}

TEST_CASE("merging by weights: weighted mean and sum, exactly", "[image]") {
    file::Buffer a = makeBuffer(2, 2, {"R", "G"}, 1, 0);
    file::Buffer b = makeBuffer(2, 2, {"G", "R"}, 3, 0); // same channels in another order
    a.planes[0] = {1, 2, 3, 4};                          // a.R
    a.planes[1] = {0, 0, 8, 8};                          // a.G
    b.planes[1] = {5, 6, 7, 8};                          // b.R
    b.planes[0] = {4, 4, 0, 0};                          // b.G
    a.sampleCounts = {1, 1, 2, 2};
    b.sampleCounts = {3, 3, 3, 3};
    const std::vector<std::string> names = {"a.lts", "b.lts"};
    const std::vector<file::Buffer> both = {a, b};

    const file::Buffer m = mergeBuffers(both, names);
    CHECK(m.channels == std::vector<std::string>{"R", "G"});
    CHECK(m.weight == 4);
    // (1 * a + 3 * b) / 4, every value exact in float.
    CHECK(m.planes[0] == std::vector<float>{4, 5, 6, 7});
    CHECK(m.planes[1] == std::vector<float>{3, 3, 2, 2});
    CHECK(m.sampleCounts == std::vector<uint32_t>{4, 4, 5, 5});

    std::vector<file::Buffer> sums = both;
    for (auto& s : sums)
        s.combine = "sum";
    const file::Buffer s = mergeBuffers(sums, names);
    CHECK(s.planes[0] == std::vector<float>{6, 8, 10, 12});
    CHECK(s.weight == 4);

    // Sample counts only survive when every input has them.
    std::vector<file::Buffer> noCounts = both;
    noCounts[1].sampleCounts.clear();
    CHECK(mergeBuffers(noCounts, names).sampleCounts.empty());
}

TEST_CASE("merging mismatched buffers fails naming both files", "[image]") {
    const std::vector<std::string> names = {"a.lts", "b.exr"};
    const file::Buffer a = makeBuffer(2, 2, {"R", "G", "B"}, 1, 0);
    auto fails = [&](const file::Buffer& b, const std::string& what) {
        const std::vector<file::Buffer> both = {a, b};
        const std::string msg = test::errorOf([&] { (void)mergeBuffers(both, names); });
        CHECK_THAT(msg, Catch::Contains("a.lts") && Catch::Contains("b.exr") && Catch::Contains(what));
    };
    fails(makeBuffer(3, 2, {"R", "G", "B"}, 1, 0), "sizes differ (2x2 and 3x2)");
    fails(makeBuffer(2, 2, {"R", "G", "B", "A"}, 1, 0), "channels differ (R,G,B and R,G,B,A)");
    file::Buffer sum = a;
    sum.combine = "sum";
    fails(sum, "combine rules differ");
    // A weight-0 buffer beside others merges (it contributes nothing); only a total of 0 is an error.
    const std::vector<file::Buffer> oneEmpty = {a, makeBuffer(2, 2, {"R", "G", "B"}, 0, 0)};
    CHECK(mergeBuffers(oneEmpty, names).planes == a.planes);
    const std::vector<file::Buffer> zero = {makeBuffer(2, 2, {"R"}, 0, 0), makeBuffer(2, 2, {"R"}, 0, 0)};
    CHECK_THAT(test::errorOf([&] { (void)mergeBuffers(zero, names); }), Catch::Contains("total weight 0"));
}

TEST_CASE("failed image writes leave nothing under the final name", "[image]") {
    test::TempDir dir;
    const file::Buffer good = makeBuffer(4, 4, {"R", "G", "B"}, 1, 0);

    SECTION("directory cannot hold the file") {
        // A regular file as the parent directory fails even for root, unlike a read-only directory.
        const std::string notDir = dir.write("plain", "x");
        for (const std::string ext : {".exr", ".png"}) {
            const std::string path = notDir + "/out" + ext;
            const std::string msg = test::errorOf([&] {
                if (ext == ".exr")
                    writeExr(path, good, nlohmann::json::object());
                else
                    writePng(path, good, 0);
            });
            CHECK_THAT(msg, Catch::StartsWith(path));
        }
        CHECK(leftovers(dir.path) == std::vector<std::string>{"plain"});
    }
    SECTION("invalid buffer: the previous file is untouched, no temporary file") {
        const std::string path = dir.write("out.exr", "previous");
        file::Buffer bad = good;
        bad.planes[1].pop_back();
        CHECK_THAT(test::errorOf([&] { writeExr(path, bad, nlohmann::json::object()); }),
                   Catch::Contains(path) && Catch::Contains("plane 'G' has 15 values, expected 16"));
        bad = good;
        bad.channels[2] = "R";
        CHECK_THAT(test::errorOf([&] { writePng(path, bad, 0); }), Catch::Contains("'R' twice"));
        CHECK(leftovers(dir.path) == std::vector<std::string>{"out.exr"});
        std::ifstream in(path);
        CHECK(std::string(std::istreambuf_iterator<char>(in), {}) == "previous");
    }
    SECTION("the rename fails: the temporary file is removed") {
        // The final name is a non-empty directory, so the image is written but cannot be renamed.
        fs::create_directories(dir.path / "out.exr" / "inside");
        CHECK_THAT(test::errorOf([&] { writeExr(dir.file("out.exr"), good, nlohmann::json::object()); }),
                   Catch::Contains("cannot rename"));
        CHECK(leftovers(dir.path) == std::vector<std::string>{"out.exr"});
    }
}

TEST_CASE("an EXR's header sizes are checked against the file and memory before OpenEXR reads it", "[image]") {
    test::TempDir dir;
    const std::string path = dir.file("checked.exr");
    writeExr(path, makeBuffer(3, 2, {"R", "G", "B", "dx.R"}, 1, 0), nlohmann::json{{"producer", "test"}});
    const std::vector<ExrPartLayout> one = scanExrHeaders(path);
    REQUIRE(one.size() == 1);
    CHECK((one[0].width == 3 && one[0].height == 2 && one[0].channels == 4));
    CHECK(one[0].chunks == 1); // ZIP: 16 scanlines a chunk

    // Two parts (OpenImageIO writes subimages as the parts of a multi-part file).
    const std::string multi = dir.file("multi.exr");
    std::vector<OIIO::ImageSpec> specs = {OIIO::ImageSpec(2, 2, 3, OIIO::TypeDesc::FLOAT),
                                          OIIO::ImageSpec(4, 1, 1, OIIO::TypeDesc::FLOAT)};
    for (auto& spec : specs) { // a multi-part file's parts share the display window
        spec.full_width = 4;
        spec.full_height = 2;
    }
    specs[0].attribute("oiio:subimagename", "first");
    specs[1].attribute("oiio:subimagename", "second");
    auto out = OIIO::ImageOutput::create(multi);
    REQUIRE(out);
    const bool opened = out->open(multi, int(specs.size()), specs.data());
    INFO(out->geterror());
    REQUIRE(opened);
    const std::vector<float> pixels(12, 0.5f);
    REQUIRE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
    REQUIRE(out->open(multi, specs[1], OIIO::ImageOutput::AppendSubimage));
    REQUIRE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
    REQUIRE(out->close());
    const std::vector<ExrPartLayout> two = scanExrHeaders(multi);
    REQUIRE(two.size() == 2);
    CHECK((two[0].width == 2 && two[0].height == 2 && two[0].channels == 3));
    CHECK((two[1].width == 4 && two[1].height == 1 && two[1].channels == 1));

    std::ifstream in(path, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto damaged = [&](const std::string& name, size_t at, const std::string& with,
                             size_t cut = std::string::npos) {
        std::string copy = bytes.substr(0, cut);
        if (at != std::string::npos) copy.replace(at, with.size(), with);
        return dir.write(name, copy);
    };
    // An attribute declaring 2^31 - 1 bytes: OpenEXR's C++ library would allocate them before finding the file
    // too short.
    const size_t info = bytes.find(std::string("lt:info\0string\0", 15));
    REQUIRE(info != std::string::npos);
    const std::string huge = damaged("huge.exr", info + 15, std::string("\xff\xff\xff\x7f", 4));
    CHECK_THAT(test::errorOf([&] { (void)readExr(huge); }),
               Catch::StartsWith(huge + ": damaged EXR header: ") && Catch::Contains("lt:info"));
    const std::string cut = damaged("cut.exr", std::string::npos, "", info + 3);
    CHECK_THAT(test::errorOf([&] { (void)readExr(cut); }), Catch::StartsWith(cut + ": damaged EXR header: "));
    const size_t window = bytes.find(std::string("dataWindow\0box2i\0\x10\0\0\0", 21));
    REQUIRE(window != std::string::npos);
    const std::string empty = damaged("empty.exr", window + 21 + 8, std::string("\xfe\xff\xff\xff", 4)); // xMax -2
    CHECK_THAT(test::errorOf([&] { (void)readExr(empty); }), Catch::StartsWith(empty + ": damaged EXR header: "));

    // What reading takes is checked against memory first: 6 pixels x 4 float channels + one 8-byte chunk offset.
    struct Restore {
        ~Restore() { unsetenv("LT_MEMORY_LIMIT"); }
    } restore;
    setenv("LT_MEMORY_LIMIT", "103", 1);
    CHECK(test::errorOf([&] { (void)readExr(path); }) ==
          path + ": an EXR of 3x2 pixels and 4 channels needs 104 bytes of memory, more than the 103 bytes available");
    setenv("LT_MEMORY_LIMIT", "104", 1);
    CHECK(readExr(path).width == 3);
}
