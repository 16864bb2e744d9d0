// Scenes as published: Mitsuba 2/3 syntax read as 0.6's (one scene in both syntaxes renders bit-identically),
// version checks, leniency about properties lt does not read (and --strict), "did you mean" for a file name
// in the wrong case, texture coordinates by mesh format and syntax, and what lt-inspect reports about them.
#include <catch2/catch.hpp>

#include <cmath>

#include "math/constants.h"
#include "util/error.h"
#include "sampling/render.h"
#include "scene/mitsuba3_syntax.h"
#include "scene/scene.h"
#include "scene/scene_features.h"
#include "test_util.h"

using namespace lt;
using Catch::Matchers::Contains;
using Catch::Matchers::Equals;
using Catch::Matchers::StartsWith;

namespace {

// One scene written twice: the Mitsuba 0.6 form and the 3.x form of every property the translation touches
// (snake_case names, int_ior, a named ref, to_uv, raw, sample_border, the conductor's default material),
// each pair meaning the same to Mitsuba.
const char* Scene06 = R"(<scene version="0.6.0">
  <integrator type="path"><integer name="maxDepth" value="5"/><integer name="rrDepth" value="3"/></integrator>
  <sensor type="perspective">
    <float name="fov" value="40"/><string name="fovAxis" value="y"/><float name="nearClip" value="0.05"/>
    <transform name="toWorld"><lookat origin="0 1.2 4" target="0 0.5 0" up="0 1 0"/></transform>
    <sampler type="independent"><integer name="sampleCount" value="8"/></sampler>
    <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="16"/>
      <integer name="cropOffsetX" value="2"/><integer name="cropWidth" value="20"/>
      <string name="pixelFormat" value="rgb"/><boolean name="highQualityEdges" value="true"/>
      <rfilter type="gaussian"><float name="stddev" value="0.4"/></rfilter></film>
  </sensor>
  <texture type="bitmap" id="tex"><string name="filename" value="tex.exr"/><float name="gamma" value="1"/>
    <float name="uscale" value="2"/><float name="vscale" value="3"/>
    <float name="uoffset" value="0.25"/><float name="voffset" value="0.5"/></texture>
  <bsdf type="plastic" id="floor"><ref name="diffuseReflectance" id="tex"/><float name="intIOR" value="1.6"/></bsdf>
  <shape type="rectangle"><transform name="toWorld"><scale value="3"/><rotate x="1" angle="-90"/></transform>
    <ref id="floor"/></shape>
  <shape type="sphere"><point name="center" x="-0.6" y="0.5" z="0"/><float name="radius" value="0.5"/>
    <bsdf type="roughconductor"><float name="alphaU" value="0.1"/><float name="alphaV" value="0.3"/>
      <string name="material" value="Au"/></bsdf></shape>
  <shape type="cube"><transform name="toWorld"><scale value="0.3"/><translate x="0.7" y="0.3"/></transform>
    <bsdf type="dielectric"><float name="intIOR" value="1.5"/><float name="extIOR" value="1.0"/></bsdf></shape>
  <shape type="rectangle"><transform name="toWorld"><translate z="-2" y="1"/></transform>
    <bsdf type="conductor"><string name="material" value="none"/></bsdf></shape>
  <shape type="sphere"><point name="center" x="1" y="3" z="1"/><float name="radius" value="0.3"/>
    <emitter type="area"><rgb name="radiance" value="10, 9, 8"/></emitter></shape>
</scene>
)";

const char* Scene3 = R"(<scene version="3.0.0">
  <default name="spp" value="8"/>
  <integrator type="path"><integer name="max_depth" value="5"/><integer name="rr_depth" value="3"/></integrator>
  <sensor type="perspective">
    <float name="fov" value="40"/><string name="fov_axis" value="y"/><float name="near_clip" value="0.05"/>
    <transform name="to_world"><lookat origin="0, 1.2, 4" target="0, 0.5, 0" up="0, 1, 0"/></transform>
    <sampler type="independent"><integer name="sample_count" value="$spp"/></sampler>
    <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="16"/>
      <integer name="crop_offset_x" value="2"/><integer name="crop_width" value="20"/>
      <string name="pixel_format" value="rgb"/><boolean name="sample_border" value="true"/>
      <rfilter type="gaussian"><float name="stddev" value="0.4"/></rfilter></film>
  </sensor>
  <texture type="bitmap" id="tex"><string name="filename" value="tex.exr"/><boolean name="raw" value="true"/>
    <transform name="to_uv"><scale x="2" y="3"/><translate x="0.25" y="0.5"/></transform></texture>
  <bsdf type="plastic" id="floor"><ref name="diffuse_reflectance" id="tex"/><float name="int_ior" value="1.6"/></bsdf>
  <shape type="rectangle"><transform name="to_world"><scale value="3"/><rotate x="1" angle="-90"/></transform>
    <ref id="floor"/></shape>
  <shape type="sphere"><point name="center" x="-0.6" y="0.5" z="0"/><float name="radius" value="0.5"/>
    <bsdf type="roughconductor"><float name="alpha_u" value="0.1"/><float name="alpha_v" value="0.3"/>
      <string name="material" value="Au"/></bsdf></shape>
  <shape type="cube"><transform name="to_world"><scale value="0.3"/><translate x="0.7" y="0.3"/></transform>
    <bsdf type="dielectric"><float name="int_ior" value="1.5"/><float name="ext_ior" value="1.0"/></bsdf></shape>
  <shape type="rectangle"><transform name="to_world"><translate z="-2" y="1"/></transform>
    <bsdf type="conductor"/></shape>
  <shape type="sphere"><point name="center" x="1" y="3" z="1"/><float name="radius" value="0.3"/>
    <emitter type="area"><rgb name="radiance" value="10, 9, 8"/></emitter></shape>
</scene>
)";

std::vector<float> render(const Scene& scene, int spp) {
    SampleFilm film(scene.camera);
    RenderSettings rs;
    rs.paths.maxDepth = scene.integrator.maxDepth;
    rs.paths.rrDepth = scene.integrator.rrDepth;
    rs.spp = spp;
    rs.seed = 7;
    (void)lt::render(scene, *test::makePixelEstimator(test::PixelMethod::Bdpt, scene, rs.paths), rs, film,
                     RunControl(2));
    return film.develop();
}

std::string loadError(const std::string& file, UnknownProperties unknown = UnknownProperties::Warn) {
    return test::errorOf([&] { (void)loadScene(file, {}, unknown); });
}

bool contains(const std::vector<std::string>& list, const std::string& s) {
    return std::find(list.begin(), list.end(), s) != list.end();
}

} // namespace

TEST_CASE("Mitsuba 3 names in 0.6's vocabulary", "[loader][syntax]") {
    CHECK(mitsuba3PropertyName("to_world") == "toWorld");
    CHECK(mitsuba3PropertyName("alpha_u") == "alphaU");
    CHECK(mitsuba3PropertyName("crop_offset_x") == "cropOffsetX");
    CHECK(mitsuba3PropertyName("specular_reflectance") == "specularReflectance");
    CHECK(mitsuba3PropertyName("int_ior") == "intIOR");
    CHECK(mitsuba3PropertyName("ext_ior") == "extIOR");
    CHECK(mitsuba3PropertyName("sample_border") == "highQualityEdges");
    CHECK(mitsuba3PropertyName("radius") == "radius");
    CHECK(mitsuba3PropertyTag("int") == "integer");
    CHECK(mitsuba3Spelling("toWorld") == "to_world");
    CHECK(mitsuba3Spelling("intIOR") == "int_ior");
    CHECK(mitsuba3Spelling("cropOffsetX") == "crop_offset_x");
    CHECK(mitsuba3PropertyTag("float") == "float");
    CHECK(sceneSyntaxOfVersion("0.6.0") == SceneSyntax::Mitsuba06);
    CHECK(sceneSyntaxOfVersion("0.4.1") == SceneSyntax::Mitsuba06);
    CHECK(sceneSyntaxOfVersion("") == SceneSyntax::Mitsuba06);
    CHECK(sceneSyntaxOfVersion("2.1.0") == SceneSyntax::Mitsuba3);
    CHECK(sceneSyntaxOfVersion("3.5.2") == SceneSyntax::Mitsuba3);
    for (const char* v : {"0.3.0", "1.0.0", "4.0.0", "three", "0.7.0"})
        CHECK_THAT(test::errorOf([&] { (void)sceneSyntaxOfVersion(v); }), Contains("is not one lt reads"));
}

TEST_CASE("a scene written in Mitsuba 0.6 and in Mitsuba 3 syntax renders bit-identically", "[loader][syntax]") {
    test::TempDir dir;
    std::vector<float> texels;
    for (int i = 0; i < 4 * 4; ++i)
        for (int c = 0; c < 3; ++c)
            texels.push_back(float(0.1 + 0.05 * i + 0.2 * c));
    test::writeRgbExr(dir.file("tex.exr"), 4, 4, texels);
    const auto a = loadScene(dir.write("scene06.xml", Scene06));
    const auto b = loadScene(dir.write("scene3.xml", Scene3));
    CHECK(a->warnings.empty());
    CHECK(b->warnings.empty());
    // Every property was read or is a known hint: the 3.x file's hints under their written names.
    CHECK(contains(a->ignoredHints, "film hdrfilm: pixelFormat"));
    CHECK(contains(b->ignoredHints, "film hdrfilm: pixel_format"));
    CHECK(contains(b->ignoredHints, "film hdrfilm: sample_border"));
    CHECK(b->integrator.maxDepth == 5);
    CHECK(b->integrator.rrDepth == 3);
    CHECK(b->integrator.sampleCount == 8);
    CHECK(b->camera.film().cropX == 2);
    REQUIRE(b->shapes.size() == a->shapes.size());
    const auto imageA = render(*a, 4);
    const auto imageB = render(*b, 4);
    REQUIRE(imageA.size() == imageB.size());
    size_t different = 0;
    for (size_t i = 0; i < imageA.size(); ++i)
        different += imageA[i] != imageB[i];
    CHECK(different == 0);
    // Not trivially equal: the image has light in it.
    double sum = 0;
    for (float v : imageA)
        sum += v;
    CHECK(sum > 0);
}

TEST_CASE("Mitsuba 3 plugin differences", "[loader][syntax]") {
    test::TempDir dir;
    auto scene3 = [&](const std::string& body) {
        return dir.write("s.xml", "<scene version=\"3.0.0\">\n" + body + "\n</scene>\n");
    };
    SECTION("a conductor without material is a mirror in Mitsuba 3, copper in 0.6") {
        const auto s3 = loadScene(scene3(R"(<shape type="sphere"><bsdf type="conductor"/></shape>)"));
        const auto s06 = loadScene(dir.write("c.xml", R"(<scene version="0.6.0">
            <shape type="sphere"><bsdf type="conductor"/></shape></scene>)"));
        // A mirror reflects all of every channel; copper reflects red more than blue.
        auto reflectance = [&](const Scene& s) {
            const Bsdf& bsdf = *s.bsdfs[size_t(s.shapes[0].bsdf)].bsdf;
            const auto sample =
                bsdf.sample(normalize(Vec3(0.3, 0, 1)), {0.5, 0.5}, Transport::Radiance, 0.5, {0.5, 0.5});
            REQUIRE(sample);
            return sample->weight;
        };
        const Spectrum mirror = reflectance(*s3), copper = reflectance(*s06);
        CHECK(mirror[0] == Approx(1.0));
        CHECK(mirror[2] == Approx(1.0));
        CHECK(copper[0] > copper[2] + 0.1);
    }
    SECTION("to_uv is applied as uv' = M uv, scale first here, then the translation") {
        // M = T(0.25, 0.5) S(2, 3). At uv (0.1, 0.1): uv' = (0.45, 0.8), checks (int(0.9), int(1.6)) = (0, 1), odd:
        // color1. At (0.3, 0.1): (0.85, 0.8), checks (1, 1), even: color0. (S (uv + t) would swap them.)
        const auto s = loadScene(scene3(R"(<bsdf type="diffuse" id="d"><texture type="checkerboard" name="reflectance">
  <rgb name="color0" value="0.8"/><rgb name="color1" value="0.1"/>
  <transform name="to_uv"><scale x="2" y="3"/><translate x="0.25" y="0.5"/></transform></texture></bsdf>)"));
        const Bsdf& d = *s->bsdfs.at(0).bsdf;
        const Vec3 up(0, 0, 1);
        CHECK(d.eval(up, up, {0.1, 0.1}, Transport::Radiance).r == Approx(0.1 / Pi));
        CHECK(d.eval(up, up, {0.3, 0.1}, Transport::Radiance).r == Approx(0.8 / Pi));
    }
    SECTION("a conductor with eta alone takes k from the mirror, as Mitsuba 3") {
        const auto s = loadScene(scene3(R"(<bsdf type="conductor" id="c"><rgb name="eta" value="0.2"/></bsdf>)"));
        CHECK(s->warnings.empty());
        CHECK(s->bsdfs.at(0).bsdf->typeName() == "conductor");
    }
    SECTION("a 0.6 name in a 3.x file is refused with its 3.x spelling") {
        const std::string f = scene3(R"(<shape type="sphere"><transform name="toWorld"/></shape>)");
        CHECK_THAT(loadError(f),
                   Equals(f + ":2: <transform>: 'toWorld' is Mitsuba 0.6 spelling, but this file declares "
                              "a 3.x version (write 'to_world')"));
        const std::string g = scene3(R"(<bsdf type="dielectric"><float name="intIOR" value="1.5"/></bsdf>)");
        CHECK_THAT(loadError(g), Contains("(write 'int_ior')"));
    }
    SECTION("to_uv that rotates has no 0.6 form") {
        const std::string f = scene3(R"(<texture type="checkerboard" id="t"/>
<texture type="bitmap" id="b"><string name="filename" value="x.exr"/>
  <transform name="to_uv"><rotate z="1" angle="30"/></transform></texture>)");
        test::writeRgbExr(dir.file("x.exr"), 1, 1, {1, 1, 1});
        CHECK_THAT(loadError(f),
                   Contains(f + ":3: <texture type=\"bitmap\" id=\"b\">: to_uv must scale and translate"));
    }
    SECTION("an unknown 3.x property keeps its written name in the warning") {
        const std::string f = scene3(R"(<shape type="sphere"><float name="some_option" value="1"/></shape>)");
        const auto s = loadScene(f);
        REQUIRE(s->warnings.size() == 1);
        CHECK_THAT(s->warnings[0], Contains(f + ":2: <shape type=\"sphere\">: property 'some_option' is not read"));
    }
    SECTION("Mitsuba 3's sunsky is another model: refused, never read as 0.6's") {
        const std::string f = scene3(R"(<emitter type="sunsky"><float name="turbidity" value="3"/></emitter>)");
        CHECK_THAT(loadError(f),
                   StartsWith(f + ":2: <emitter type=\"sunsky\">: Mitsuba 3's sunsky is not Mitsuba 0.6's"));
    }
    SECTION("a version lt does not read is refused with file and line") {
        const std::string f = dir.write("v.xml", "<scene version=\"1.0.0\">\n</scene>\n");
        CHECK_THAT(loadError(f), Contains(f + ":1: <scene>: version \"1.0.0\" is not one lt reads"));
    }
}

TEST_CASE("texture coordinates by mesh format and syntax", "[loader][syntax]") {
    test::TempDir dir;
    dir.write("quad.obj",
              "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0.25\nvt 1 0.25\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n");
    dir.write("quad.ply", "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                          "property float z\nproperty float u\nproperty float v\nelement face 1\n"
                          "property list uchar int vertex_indices\nend_header\n"
                          "0 0 0 0 0.25\n1 0 0 1 0.25\n1 1 0 1 1\n0 1 0 0 1\n4 0 1 2 3\n");
    struct Case {
        const char* version;
        const char* mesh;
        const char* flip; // "" (the format's default), "true" or "false"
        float v0;         // the first vertex's v after loading
        bool unread;      // the flip option is a property lt (like that Mitsuba) does not read
    };
    const Case cases[] = {
        {"0.6.0", "quad.obj", "", 0.75f, false},     {"0.6.0", "quad.obj", "false", 0.25f, false},
        {"0.6.0", "quad.ply", "", 0.25f, false},     {"0.6.0", "quad.ply", "true", 0.25f, true},
        {"3.0.0", "quad.obj", "", 0.75f, false},     {"3.0.0", "quad.ply", "", 0.25f, false},
        {"3.0.0", "quad.ply", "true", 0.75f, false},
    };
    for (const Case& c : cases) {
        const bool three = c.version[0] == '3';
        const std::string type = std::string(c.mesh).substr(5);
        std::string body = "<shape type=\"" + type + "\"><string name=\"filename\" value=\"" + c.mesh + "\"/>";
        if (*c.flip)
            body += std::string("<boolean name=\"") + (three ? "flip_tex_coords" : "flipTexCoords") + "\" value=\"" +
                    c.flip + "\"/>";
        body += "</shape>";
        const std::string f =
            dir.write("uv.xml", std::string("<scene version=\"") + c.version + "\">\n" + body + "\n</scene>\n");
        INFO(c.version << ' ' << c.mesh << " flip '" << c.flip << "'");
        const auto s = loadScene(f);
        REQUIRE(s->shapes.size() == 1);
        CHECK(s->shapes[0].mesh().uvs.at(0).y == Approx(c.v0));
        CHECK(s->warnings.size() == (c.unread ? 1u : 0u));
    }
}

TEST_CASE("properties lt does not read: a warning once per plugin and property, an error with --strict",
          "[loader][syntax]") {
    test::TempDir dir;
    const std::string f = dir.write("lenient.xml", R"(<scene version="0.6.0">
<sensor type="perspective"><float name="fov" value="30"/>
  <float name="apertureRadius" value="0.1"/></sensor>
<shape type="sphere"><bsdf type="conductor"><float name="alpha" value="0.2"/></bsdf></shape>
<shape type="sphere"><point name="center" x="3" y="0" z="0"/>
  <bsdf type="conductor"><float name="alpha" value="0.2"/></bsdf></shape>
<integrator type="path"><boolean name="usePathGuiding" value="true"/></integrator>
</scene>
)");
    const auto s = loadScene(f);
    REQUIRE(s->warnings.size() == 2);
    CHECK_THAT(s->warnings[0],
               Equals(f + ":3: <sensor type=\"perspective\">: property 'apertureRadius' is not read by lt "
                          "and was ignored; --strict makes this an error"));
    CHECK_THAT(s->warnings[1], Equals(f + ":4: <bsdf type=\"conductor\">: property 'alpha' is not read by lt and was "
                                          "ignored (also at 1 other place(s)); --strict makes this an error"));
    // An integrator's options are the tools' business: a hint, not a warning.
    CHECK(contains(s->ignoredHints, "integrator path: usePathGuiding"));
    CHECK_THAT(loadError(f, UnknownProperties::Fail),
               Equals(f +
                      ":3: <sensor type=\"perspective\"> does not read the property 'apertureRadius' (an error with "
                      "--strict; without it lt warns and ignores it, as Mitsuba 0.6 does)"));
}

TEST_CASE("a named ref its parent does not read is an error; a shape instanced twice is checked once",
          "[loader][syntax]") {
    test::TempDir dir;
    const std::string f = dir.write("refs.xml", R"(<scene version="0.6.0">
<texture type="checkerboard" id="wood"/>
<bsdf type="diffuse" id="a"><ref name="reflectance" id="wood"/></bsdf>
<bsdf type="roughconductor" id="b"><ref name="diffuseReflectance" id="wood"/></bsdf>
</scene>
)");
    // Consumed by the first BSDF, not by the second: still an error for the second.
    CHECK_THAT(loadError(f), Contains("not used by its <bsdf type=\"roughconductor\"> (check its name)"));
    // Mitsuba 0.6's diffuse takes diffuseReflectance as well as reflectance.
    const auto d = loadScene(dir.write("diffuse.xml", R"(<scene version="0.6.0">
<texture type="checkerboard" id="wood"><rgb name="color0" value="0.7"/><rgb name="color1" value="0.7"/></texture>
<bsdf type="diffuse" id="b"><ref name="diffuseReflectance" id="wood"/></bsdf></scene>)"));
    const Vec3 up(0, 0, 1);
    CHECK(d->bsdfs.at(0).bsdf->eval(up, up, {0.3, 0.3}, Transport::Radiance).r == Approx(0.7 / Pi));
    const auto g = loadScene(dir.write("group.xml", R"(<scene version="0.6.0">
<shape type="shapegroup" id="g"><shape type="sphere"><float name="radiuss" value="1"/></shape></shape>
<shape type="instance"><ref id="g"/></shape>
<shape type="instance"><ref id="g"/></shape>
</scene>)"));
    REQUIRE(g->warnings.size() == 1);
    CHECK_THAT(g->warnings[0], !Contains("other place"));
}

TEST_CASE("a missing file whose name differs only in case: did you mean", "[loader][syntax]") {
    test::TempDir dir;
    dir.write("Meshes/DarkOak.OBJ", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const std::string f = dir.write("scene.xml", R"(<scene version="0.6.0">
<shape type="obj"><string name="filename" value="meshes/darkoak.obj"/></shape>
</scene>
)");
    CHECK_THAT(loadError(f), Equals(f + ":2: <shape type=\"obj\">: file not found: " + dir.file("meshes/darkoak.obj") +
                                    " (did you mean " + dir.file("Meshes/DarkOak.OBJ") + "?)"));
    CHECK_THAT(loadError(dir.file("Scene.XML")),
               Equals(dir.file("Scene.XML") + ": cannot open scene file (did you mean " + f + "?)"));
}

TEST_CASE("lt-inspect's features: delta lights named by type, BSDFs counted per declaration", "[loader][syntax]") {
    test::TempDir dir;
    SECTION("an environment-lit scene has no delta lights, and says which emitters it has") {
        const auto s = loadScene(dir.write("env.xml", R"(<scene version="0.6.0">
<shape type="sphere"/><emitter type="constant"/></scene>)"));
        const SceneFeatures f = analyzeScene(*s);
        CHECK_FALSE(f.deltaLights);
        CHECK_THAT(f.deltaLightReason, Contains("constant") && !Contains("area"));
    }
    SECTION("a point light is named") {
        const auto s = loadScene(dir.write("point.xml", R"(<scene version="0.6.0">
<shape type="sphere"/><emitter type="point"/></scene>)"));
        const SceneFeatures f = analyzeScene(*s);
        CHECK(f.deltaLights);
        CHECK_THAT(f.deltaLightReason, Contains("point"));
    }
    SECTION("one glossy BSDF referenced by name from three shapes is one BSDF") {
        const auto s = loadScene(dir.write("refs.xml", R"(<scene version="0.6.0">
<bsdf type="roughconductor" id="gloss"/>
<shape type="sphere"><ref name="bsdf" id="gloss"/></shape>
<shape type="sphere"><point name="center" x="3" y="0" z="0"/><ref name="bsdf" id="gloss"/></shape>
<shape type="sphere"><point name="center" x="6" y="0" z="0"/><ref id="gloss"/></shape>
</scene>)"));
        const SceneFeatures f = analyzeScene(*s);
        CHECK(s->bsdfs.size() == 1);
        CHECK(f.glossyBsdfs == 1);
        CHECK(f.bsdfTypes.at("roughconductor") == 1);
        CHECK_THAT(f.glossyReason, Equals("glossy BSDFs: 'gloss' (roughconductor)"));
    }
}

TEST_CASE("a perspective sensor without fov takes Mitsuba's 50 mm lens; a scene without a sensor, Mitsuba's",
          "[loader][syntax]") {
    test::TempDir dir;
    // The lens's diagonal field of view (the 36 x 24 mm frame's diagonal, 43.27 mm) spans the film's diagonal:
    // on a 40 x 30 film (diagonal 50 px) fov_x = 2 atan(tan(fov_d / 2) 40 / 50).
    auto fovX = [](double mm) {
        const double tanHalfDiagonal = std::sqrt(36.0 * 36.0 + 24.0 * 24.0) / (2 * mm);
        return 2 * std::atan(tanHalfDiagonal * 40 / 50) * 180 / Pi;
    };
    const auto s = loadScene(dir.write("lens.xml", R"(<scene version="0.6.0">
<sensor type="perspective"><film type="hdrfilm"><integer name="width" value="40"/><integer name="height" value="30"/>
</film></sensor></scene>)"));
    CHECK(s->camera.fovX() == Approx(fovX(50)).epsilon(1e-9));
    const auto t = loadScene(dir.write("lens35.xml", R"(<scene version="0.6.0">
<sensor type="perspective"><string name="focalLength" value="35mm"/><string name="fovAxis" value="y"/>
<film type="hdrfilm"><integer name="width" value="40"/><integer name="height" value="30"/></film></sensor></scene>)"));
    CHECK(t->camera.fovX() == Approx(fovX(35)).epsilon(1e-9));
    CHECK(t->warnings.empty()); // Mitsuba reads fovAxis with a focal length too (and ignores it)
    // No sensor: fov 45 along x, in front of the shapes' box (z below its minimum) far enough back to see its
    // larger extent in x and y: a box of [-1, 3] x [0, 2] x [0, 1] is seen from (1, 1, -4 / (2 tan 22.5 deg)).
    const auto u = loadScene(dir.write("nosensor.xml", R"(<scene version="0.6.0">
<shape type="cube"><transform name="toWorld"><scale x="2" y="1" z="0.5"/><translate x="1" y="1" z="0.5"/></transform>
</shape></scene>)"));
    CHECK(u->camera.fovX() == Approx(45));
    const double distance = 4 / (2 * std::tan(22.5 * Pi / 180));
    CHECK(u->camera.position().x == Approx(1));
    CHECK(u->camera.position().y == Approx(1));
    CHECK(u->camera.position().z == Approx(-distance));
    CHECK(u->camera.forward().z == Approx(1));
    CHECK(u->camera.film().width == 768);
}
