// The Mitsuba XML loader: the shipped scenes (the three public ones among them), every element kind, and every kind of
// bad input with its exact error line.
#include <catch2/catch.hpp>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <filesystem>

#include "math/constants.h"
#include "util/error.h"
#include "scene/scene.h"
#include "scene/scene_features.h"
#include "test_util.h"

using namespace lt;
using Catch::Matchers::Contains;
using Catch::Matchers::Equals;
using Catch::Matchers::StartsWith;

namespace {

// A scene file whose body starts on line 2 (line 1 is the <scene> tag).
std::string sceneFile(const test::TempDir& dir, const std::string& body, const std::string& name = "scene.xml") {
    return dir.write(name, "<scene version=\"0.5.0\">\n" + body + "\n</scene>\n");
}

std::string errorOf(const std::string& file, const std::map<std::string, std::string>& params = {}) {
    return test::errorOf([&] { (void)loadScene(file, params); });
}

const Shape& onlyShape(const Scene& s) {
    REQUIRE(s.shapes.size() == 1);
    return s.shapes[0];
}

void writeExr(const std::string& path, int w, int h, float value) {
    auto out = OIIO::ImageOutput::create(path);
    REQUIRE(out);
    OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::FLOAT);
    REQUIRE(out->open(path, spec));
    std::vector<float> px(size_t(w) * h * 3, value);
    REQUIRE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
    out->close();
}

} // namespace

TEST_CASE("the three public scenes load unmodified", "[loader]") {
    SECTION("cornell-box") {
        const auto s = loadScene(test::shippedScene("cornell-box"));
        CHECK(s->shapes.size() == 8);
        CHECK(s->emitters.size() == 1);
        CHECK(s->camera.film().width == 1024);
        CHECK(s->camera.film().height == 1024);
        CHECK(s->camera.film().filter.type == PixelFilter::Type::Tent);
        CHECK(s->integrator.maxDepth == 65);
        CHECK(s->integrator.sampleCount == 64);
        const SceneFeatures f = analyzeScene(*s);
        CHECK(f.triangles == 5 * 2 + 2 * 12 + 2);
        CHECK(f.bsdfTypes.at("twosided(diffuse)") == 8);
        CHECK_FALSE(f.specularChains);
        CHECK_FALSE(f.glossySurfaces);
        // ldrfilm's gamma, banner etc. are reported as ignored hints, not errors.
        CHECK(std::find(s->ignoredHints.begin(), s->ignoredHints.end(), "film ldrfilm: gamma") != s->ignoredHints.end());
        // The red wall sits at x = -1, the box spans y in [0, 2].
        CHECK(s->bounds.lo.x == Approx(-1).margin(1e-5));
        CHECK(s->bounds.hi.y == Approx(2).margin(1e-5));
    }
    SECTION("veach-mis") {
        const auto s = loadScene(test::shippedScene("veach-mis"));
        CHECK(s->shapes.size() == 9);
        CHECK(s->emitters.size() == 3);
        CHECK(s->integrator.maxDepth == 3);
        CHECK(s->camera.film().width == 1280);
        const SceneFeatures f = analyzeScene(*s);
        CHECK(f.spheres == 3);
        CHECK(f.glossySurfaces);
        CHECK(f.minGlossyRoughness == Approx(0.01));
        CHECK_FALSE(f.specularChains);
    }
    SECTION("veach-bidir") {
        const auto s = loadScene(test::shippedScene("veach-bidir"));
        CHECK(s->shapes.size() == 14);
        CHECK(s->emitters.size() == 2);
        CHECK(s->integrator.maxDepth == 7);
        const SceneFeatures f = analyzeScene(*s);
        CHECK(f.specularChains);   // the glass egg
        CHECK(f.glossySurfaces);   // the lamp
        CHECK(f.triangles > 10000);
    }
}

TEST_CASE("the scenes shipped in scenes/ load and say what they need", "[loader]") {
    const auto a = loadScene(test::shippedScene("cornell-spheres"));
    CHECK(analyzeScene(*a).specularChains);
    CHECK(analyzeScene(*a).spheres == 2);
    const auto b = loadScene(test::shippedScene("portal-room"));
    CHECK(analyzeScene(*b).hasPortals);
    CHECK(analyzeScene(*b).portals == 1);
    const auto c = loadScene(test::shippedScene("glossy-sky"));
    CHECK(analyzeScene(*c).environmentLight);
    CHECK(analyzeScene(*c).glossySurfaces);
    CHECK(analyzeScene(*c).disks == 1);
    const auto d = loadScene(test::shippedScene("window-room"));
    CHECK(analyzeScene(*d).portals == 1);
    CHECK(analyzeScene(*d).environmentLight);
    for (const char* name : {"door-ajar", "three-planes"})
        CHECK(analyzeScene(*loadScene(test::shippedScene(name))).portals == 1);
    // Every shipped scene reads without a property lt does not know (a typo would otherwise only warn).
    for (const auto& entry : std::filesystem::directory_iterator(std::string(LT_SOURCE_DIR) + "/scenes"))
        if (std::filesystem::exists(entry.path() / "scene.xml")) {
            INFO(entry.path());
            CHECK_NOTHROW(loadScene((entry.path() / "scene.xml").string(), {}, UnknownProperties::Fail));
        }
}

TEST_CASE("shapes: every kind, with transforms and flipNormals", "[loader]") {
    test::TempDir dir;
    SECTION("rectangle scaled") {
        const auto s = loadScene(sceneFile(dir, R"(<shape type="rectangle"><transform name="toWorld"><scale x="2" y="3"/></transform></shape>)"));
        CHECK(onlyShape(*s).area() == Approx(24.0));
        CHECK(onlyShape(*s).mesh().triangles.size() == 2);
    }
    SECTION("cube has 12 outward triangles") {
        const auto s = loadScene(sceneFile(dir, R"(<shape type="cube"/>)"));
        CHECK(onlyShape(*s).area() == Approx(24.0));
        const SurfaceInteraction si = onlyShape(*s).surfaceAt(0, {0.2, 0.3});
        CHECK(dot(si.ng, si.p) > 0);   // outward: the normal points away from the cube's center
    }
    SECTION("sphere: center, radius and toWorld compose in document order") {
        // Mitsuba composes each new operation on the left: scale first, then translate.
        const auto s = loadScene(sceneFile(dir, R"(<shape type="sphere"><float name="radius" value="0.5"/>
            <transform name="toWorld"><scale value="2"/><translate x="1"/></transform></shape>)"));
        CHECK(onlyShape(*s).radius() == Approx(1.0));
        CHECK(onlyShape(*s).center().x == Approx(1.0));
        const auto t = loadScene(sceneFile(dir, R"(<shape type="sphere"><transform name="toWorld"><translate x="1"/><scale value="2"/></transform></shape>)"));
        CHECK(onlyShape(*t).center().x == Approx(2.0));
    }
    SECTION("disk area follows its transform; flipNormals flips") {
        const auto s = loadScene(sceneFile(dir, R"(<shape type="disk"><transform name="toWorld"><scale value="0.5"/></transform>
            <boolean name="flipNormals" value="true"/></shape>)"));
        CHECK(onlyShape(*s).area() == Approx(Pi * 0.25));
        CHECK(onlyShape(*s).surfaceAt(0, {0.5, 0.1}).ng.z == Approx(-1.0));
    }
    SECTION("obj with faceNormals drops the vertex normals") {
        dir.write("quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nvn 0 0 1\nvn 0 0 1\nvn 0 0 1\n"
                              "f 1//1 2//2 3//3 4//4\n");
        const auto s = loadScene(sceneFile(dir, R"(<shape type="obj"><string name="filename" value="quad.obj"/>
            <boolean name="faceNormals" value="true"/></shape>)"));
        CHECK(onlyShape(*s).mesh().triangles.size() == 2);
        CHECK(onlyShape(*s).mesh().normals.empty());
    }
    SECTION("ply") {
        dir.write("tri.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                             "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                             "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
        const auto s = loadScene(sceneFile(dir, R"(<shape type="ply"><string name="filename" value="tri.ply"/></shape>)"));
        CHECK(onlyShape(*s).area() == Approx(0.5));
    }
    SECTION("portal shapes stay out of the geometry") {
        const auto s = loadScene(sceneFile(dir, R"(<shape type="rectangle"><boolean name="portal" value="true"/></shape>)"));
        CHECK(s->shapes[0].portal);
        Ray r;
        r.o = {0, 0, 1};
        r.d = {0, 0, -1};
        CHECK_FALSE(s->intersect(r).has_value());
    }
}

TEST_CASE("shapegroup and instance: the group's shapes placed by each instance", "[loader]") {
    test::TempDir dir;
    const auto s = loadScene(sceneFile(dir, R"(
        <shape type="shapegroup" id="pair">
            <shape type="sphere"><float name="radius" value="0.5"/><bsdf type="roughconductor" id="metal"/></shape>
            <shape type="rectangle"><transform name="toWorld"><translate x="2"/></transform></shape>
        </shape>
        <shape type="instance"><ref id="pair"/></shape>
        <shape type="instance"><ref id="pair"/><transform name="toWorld"><scale value="2"/><translate y="10"/></transform></shape>)"));
    REQUIRE(s->shapes.size() == 4);
    // The second instance scales the group by 2 and lifts it by 10: the rectangle ([-1, 1]^2 moved to x = 2)
    // spans x in [2, 6] and y in [8, 12]; the first instance's rectangle reaches down to y = -1.
    CHECK(s->bounds.hi.y == Approx(12).margin(1e-6));
    CHECK(s->bounds.hi.x == Approx(6).margin(1e-6));
    CHECK(s->bounds.lo.y == Approx(-1).margin(1e-6));
    // One declaration, one BSDF, however many instances use it (plus the rectangles' default diffuse).
    CHECK(s->bsdfs.size() == 3);
    CHECK(analyzeScene(*s).glossyBsdfs == 1);
    test::TempDir bad;
    const std::string f = sceneFile(bad, R"(<shape type="shapegroup" id="g"><shape type="sphere">
        <emitter type="area"/></shape></shape>)");
    CHECK_THAT(errorOf(f),
               Equals(f + ":2: <shape type=\"sphere\">: a shape in a shapegroup cannot emit (as in Mitsuba)"));
}

TEST_CASE("properties: defaults, $substitution, include, spectra, colours", "[loader]") {
    test::TempDir dir;
    dir.write("part.xml", R"(<scene version="0.5.0"><shape type="sphere"><float name="radius" value="$r"/></shape></scene>)");
    const std::string main = sceneFile(dir, R"(<default name="r" value="2"/><include filename="part.xml"/>)");
    CHECK(onlyShape(*loadScene(main)).radius() == Approx(2.0));
    CHECK(onlyShape(*loadScene(main, {{"r", "3"}})).radius() == Approx(3.0));   // command line wins

    const auto s = loadScene(sceneFile(dir, R"(
        <bsdf type="diffuse" id="a"><spectrum name="reflectance" value="0.25"/></bsdf>
        <bsdf type="diffuse" id="b"><spectrum name="reflectance" value="400:0.3, 700:0.3"/></bsdf>
        <bsdf type="diffuse" id="c"><srgb name="reflectance" value="#ffffff"/></bsdf>
        <bsdf type="diffuse" id="d"><rgb name="reflectance" value="0.1 0.2 0.3"/></bsdf>)"));
    REQUIRE(s->bsdfs.size() == 4);
    const Vec3 up{0, 0, 1};
    auto albedo = [&](int i) { return s->bsdfs[size_t(i)].bsdf->eval(up, up, {0, 0}, Transport::Radiance) * Pi; };
    CHECK(albedo(0).g == Approx(0.25));
    // A constant spectrum maps to the same grey in RGB (the white balance of spectrumToRgb).
    CHECK(albedo(1).r == Approx(0.3).epsilon(1e-9));
    CHECK(albedo(1).b == Approx(0.3).epsilon(1e-9));
    CHECK(albedo(2).g == Approx(1.0));
    CHECK(albedo(3).b == Approx(0.3));
}

TEST_CASE("every BSDF kind builds from XML", "[loader]") {
    test::TempDir dir;
    const auto s = loadScene(sceneFile(dir, R"(
        <bsdf type="diffuse"/>
        <bsdf type="twosided"><bsdf type="diffuse"/></bsdf>
        <bsdf type="dielectric"><float name="intIOR" value="1.33"/></bsdf>
        <bsdf type="thindielectric"><string name="intIOR" value="bk7"/></bsdf>
        <bsdf type="roughdielectric"><string name="distribution" value="ggx"/><float name="alpha" value="0.2"/></bsdf>
        <bsdf type="conductor"><string name="material" value="Au"/></bsdf>
        <bsdf type="roughconductor"><float name="alphaU" value="0.05"/><float name="alphaV" value="0.2"/>
            <rgb name="eta" value="0.2, 0.9, 1.1"/><rgb name="k" value="3.9, 2.4, 2.1"/></bsdf>
        <bsdf type="plastic"><rgb name="diffuseReflectance" value="0.3"/></bsdf>
        <bsdf type="roughplastic"><float name="alpha" value="0.3"/></bsdf>
        <bsdf type="diffuse"><texture type="checkerboard" name="reflectance"/></bsdf>
        <bsdf type="phong"><float name="exponent" value="80"/><rgb name="specularReflectance" value="0.3"/></bsdf>
        <bsdf type="ward"><string name="variant" value="ward-duer"/><float name="alpha" value="0.2"/>
            <float name="alphaV" value="0.05"/></bsdf>
        <bsdf type="blendbsdf"><float name="weight" value="0.2"/><bsdf type="diffuse"/>
            <bsdf type="roughconductor"/></bsdf>
        <bsdf type="mask"><float name="opacity" value="0.7"/><bsdf type="twosided"><bsdf type="diffuse"/></bsdf></bsdf>)"));
    REQUIRE(s->bsdfs.size() == 14);
    const char* names[] = {"diffuse",         "twosided",  "dielectric",     "thindielectric",
                           "roughdielectric", "conductor", "roughconductor", "plastic",
                           "roughplastic",    "diffuse",   "phong",          "ward",
                           "blendbsdf",       "mask"};
    for (size_t i = 0; i < 14; ++i)
        CHECK(s->bsdfs[i].bsdf->typeName() == names[i]);
    CHECK(describeBsdf(*s->bsdfs[13].bsdf) == "mask(twosided(diffuse))");
    CHECK(s->bsdfs[13].bsdf->hasDelta());
    CHECK(s->bsdfs[13].bsdf->hasTransmission());
    CHECK(describeBsdf(*s->bsdfs[12].bsdf) == "blendbsdf(diffuse, roughconductor)");
    CHECK(s->bsdfs[12].bsdf->hasGlossy());
    CHECK(s->bsdfs[12].bsdf->hasDiffuse());
    // phong's Beckmann-equivalent roughness sqrt(2 / (n + 2)); ward's alphaU defaults to alpha (Mitsuba).
    CHECK(s->bsdfs[10].bsdf->roughness({0, 0}) == Approx(std::sqrt(2.0 / 82)));
    CHECK(s->bsdfs[11].bsdf->roughness({0, 0}) == Approx(0.05));
    CHECK(s->bsdfs[11].bsdf->hasDiffuse());
    CHECK(s->warnings.empty());
    CHECK(s->bsdfs[2].bsdf->hasDelta());
    CHECK(s->bsdfs[2].bsdf->eta()->interior == Approx(1.33));
    CHECK(s->bsdfs[4].bsdf->hasGlossy());
    CHECK(s->bsdfs[4].bsdf->hasTransmission());
    // Phong's exponent and ward's alphas as textures (checkerboard: color0 at uv (0.1, 0.1), color1 at (0.6, 0.1)).
    const auto t = loadScene(sceneFile(dir, R"(
        <bsdf type="phong"><texture type="checkerboard" name="exponent"><float name="color0" value="8"/>
            <float name="color1" value="98"/></texture></bsdf>
        <bsdf type="ward"><texture type="checkerboard" name="alpha"><float name="color0" value="0.3"/>
            <float name="color1" value="0.05"/></texture><float name="alphaV" value="0.2"/></bsdf>)"),
                             {}, UnknownProperties::Fail);
    CHECK(t->bsdfs[0].bsdf->roughness({0.1, 0.1}) == Approx(std::sqrt(2.0 / 10)));
    CHECK(t->bsdfs[0].bsdf->roughness({0.6, 0.1}) == Approx(std::sqrt(2.0 / 100)));
    CHECK(t->bsdfs[1].bsdf->roughness({0.1, 0.1}) == Approx(0.2));
    CHECK(t->bsdfs[1].bsdf->roughness({0.6, 0.1}) == Approx(0.05));
}

TEST_CASE("phong and ward reflectances summing above 1 are scaled down as in Mitsuba, and the loader says so",
          "[loader]") {
    test::TempDir dir;
    const std::string f = sceneFile(dir, R"(<bsdf type="phong"><rgb name="diffuseReflectance" value="0.9"/></bsdf>
        <bsdf type="ward"><rgb name="diffuseReflectance" value="0.9"/>
            <boolean name="ensureEnergyConservation" value="false"/></bsdf>)");
    const auto s = loadScene(f);
    REQUIRE(s->warnings.size() == 1);
    CHECK_THAT(s->warnings[0], StartsWith(f + ":2: <bsdf type=\"phong\">: specularReflectance + diffuseReflectance "
                                              "exceed 1; both scaled by 0.9"));
    // f of the diffuse lobe alone (wo far from the mirror direction): 0.9 / pi scaled by 0.99 / 1.1.
    const Vec3 wi = normalize(Vec3(0.8, 0, 0.6)), wo = normalize(Vec3(0.8, 0, 0.6));
    const double expected = 0.9 / Pi * 0.99 / 1.1;
    CHECK(s->bsdfs[0].bsdf->eval(wi, wo, {0, 0}, Transport::Radiance).r == Approx(expected).epsilon(1e-6));
    CHECK(s->bsdfs[1].bsdf->eval(wi, wo, {0, 0}, Transport::Radiance).r == Approx(0.9 / Pi).epsilon(1e-9));
}

TEST_CASE("every emitter kind builds from XML", "[loader]") {
    test::TempDir dir;
    writeExr(dir.file("sky.exr"), 16, 8, 0.5f);
    const auto s = loadScene(sceneFile(dir, R"(
        <emitter type="point"><point name="position" x="0" y="2" z="0"/><rgb name="intensity" value="10"/></emitter>
        <emitter type="spot"><transform name="toWorld"><lookat origin="0,3,0" target="0,0,0" up="0,0,1"/></transform>
            <float name="cutoffAngle" value="30"/></emitter>
        <emitter type="directional"><vector name="direction" x="0" y="-1" z="0"/><spectrum name="irradiance" value="2"/></emitter>
        <emitter type="constant"><rgb name="radiance" value="0.5"/></emitter>
        <emitter type="envmap"><string name="filename" value="sky.exr"/><float name="scale" value="2"/></emitter>
        <shape type="sphere"><emitter type="area"><rgb name="radiance" value="4"/></emitter></shape>)"));
    REQUIRE(s->emitters.size() == 6);
    const char* names[] = {"point", "spot", "directional", "constant", "envmap", "area"};
    for (size_t i = 0; i < 6; ++i) CHECK(s->emitters[i]->typeName() == names[i]);
    CHECK(s->emitters[0]->isDelta());
    CHECK(s->emitters[3]->isInfinite());
    CHECK(s->emitters[5]->shape == 0);
    CHECK(s->shapes[0].emitter == 5);
    // A constant 0.5 map scaled by 2 shines with radiance 1 from every direction.
    CHECK(s->emitters[4]->evalEnvironment(normalize(Vec3(0.3, 0.5, 0.8))).g == Approx(1.0).epsilon(1e-5));
}

TEST_CASE("sky, sun and sunsky build from XML as Mitsuba 0.6 reads them", "[loader][daylight]") {
    test::TempDir dir;
    SECTION("defaults: Tokyo, 10 July 2010, 15:00; one map") {
        const auto s = loadScene(sceneFile(dir, R"(<emitter type="sunsky"/>)"));
        REQUIRE(s->emitters.size() == 1);
        CHECK(s->emitters[0]->typeName() == "sunsky");
        CHECK(s->emitters[0]->isInfinite());
        CHECK_FALSE(s->emitters[0]->isDelta());
        // In the afternoon the sun stands in the west (-x of the sky frame) and south (+z): the map is
        // brighter there than toward the north-east at the same height.
        const Spectrum west = s->emitters[0]->evalEnvironment(normalize(Vec3(-1, 1, 0.3)));
        const Spectrum east = s->emitters[0]->evalEnvironment(normalize(Vec3(1, 1, -0.3)));
        CHECK(west.luminance() > east.luminance());
    }
    SECTION("sunDirection in world space through toWorld; sunRadiusScale 0 adds a directional sun") {
        const auto s = loadScene(sceneFile(dir, R"(<emitter type="sunsky">
            <vector name="sunDirection" x="0" y="1" z="1"/><float name="sunRadiusScale" value="0"/>
            <transform name="toWorld"><rotate y="1" angle="90"/></transform></emitter>)"));
        REQUIRE(s->emitters.size() == 2);
        CHECK(s->emitters[0]->typeName() == "sunsky");
        CHECK(s->emitters[1]->typeName() == "directional");
        s->emitters[1]->setSceneBounds({}, 1);
        const DirectSample ds = s->emitters[1]->sampleDirect({0, 0, 0}, {0.5, 0.5});
        CHECK(length(ds.wi - normalize(Vec3(0, 1, 1))) < 1e-9);
    }
    SECTION("sky alone and sun alone") {
        const auto s = loadScene(sceneFile(dir, R"(<emitter type="sky"><float name="turbidity" value="5"/>
            <rgb name="albedo" value="0.1, 0.2, 0.3"/><float name="hour" value="10"/></emitter>
            <emitter type="sun"><float name="hour" value="10"/><float name="sunRadiusScale" value="3"/></emitter>)"));
        REQUIRE(s->emitters.size() == 2);
        CHECK(s->emitters[0]->typeName() == "sky");
        CHECK(s->emitters[1]->typeName() == "sun");
    }
    SECTION("errors name the file, the line and what is wrong") {
        const std::string f = dir.file("scene.xml");
        sceneFile(dir, "<emitter type=\"sunsky\">\n<float name=\"turbidity\" value=\"12\"/></emitter>");
        CHECK_THAT(errorOf(f), Equals(f + ":2: <emitter type=\"sunsky\">: turbidity must be in [1, 10]"));
        sceneFile(dir, "<emitter type=\"sky\"><float name=\"hour\" value=\"23\"/></emitter>");
        CHECK_THAT(errorOf(f), StartsWith(f + ":2: <emitter type=\"sky\">: the sun is below the horizon ("));
        sceneFile(dir, "<emitter type=\"sun\"><vector name=\"sunDirection\" x=\"0\" y=\"1\" z=\"0\"/>"
                       "<float name=\"latitude\" value=\"40\"/></emitter>");
        CHECK_THAT(errorOf(f), Equals(f + ":2: <emitter type=\"sun\">: give the sun either by sunDirection or by time "
                                          "and place, not both (latitude with sunDirection)"));
    }
}

TEST_CASE("bitmap filterType and wrap modes as Mitsuba 0.6 names them", "[loader]") {
    test::TempDir dir;
    writeExr(dir.file("t.exr"), 4, 4, 0.5f);
    auto bitmap = [&](const std::string& props) {
        return sceneFile(dir, "<bsdf type=\"diffuse\" id=\"d\">\n<texture type=\"bitmap\" name=\"reflectance\">\n"
                              "<string name=\"filename\" value=\"t.exr\"/>" +
                                  props + "</texture></bsdf>");
    };
    for (const char* ok : {R"(<string name="filterType" value="nearest"/><string name="wrapMode" value="mirror"/>)",
                           R"(<string name="filterType" value="trilinear"/><string name="wrapModeU" value="clamp"/>
                              <string name="wrapModeV" value="zero"/>)",
                           R"(<string name="wrapMode" value="one"/><string name="filterType" value="ewa"/>)"}) {
        CAPTURE(ok);
        const auto s = loadScene(bitmap(ok), {}, UnknownProperties::Fail);
        CHECK(s->bsdfs.size() == 1);
    }
    const std::string f = dir.file("scene.xml");
    bitmap(R"(<string name="wrapMode" value="wrap"/>)");
    CHECK_THAT(errorOf(f), Equals(f + ":3: <texture type=\"bitmap\">: wrap mode 'wrap' is not one of repeat, mirror, "
                                      "clamp, zero, one"));
    bitmap(R"(<string name="filterType" value="cubic"/>)");
    CHECK_THAT(errorOf(f), Equals(f + ":3: <texture type=\"bitmap\">: filterType 'cubic' is not one of ewa, trilinear, "
                                      "bilinear, nearest"));
}

TEST_CASE("bumpmap and the scale texture build from XML; a bumpmap inside another BSDF is refused",
          "[loader][bumpmap]") {
    test::TempDir dir;
    writeExr(dir.file("h.exr"), 4, 4, 0.5f);
    const auto s = loadScene(sceneFile(dir, R"(<shape type="rectangle"><bsdf type="bumpmap">
        <texture type="scale"><float name="scale" value="0.1"/><texture type="bitmap"><string name="filename" value="h.exr"/></texture></texture>
        <bsdf type="twosided"><bsdf type="diffuse"/></bsdf></bsdf></shape>)"),
                             {}, UnknownProperties::Fail);
    CHECK(s->bsdfs.at(0).bsdf->typeName() == "bumpmap");
    CHECK(describeBsdf(*s->bsdfs[0].bsdf) == "bumpmap(twosided(diffuse))");
    REQUIRE(s->shapes.at(0).bump);
    CHECK(s->shapes[0].bump->average().g == Approx(0.05));
    const std::string f = dir.file("scene.xml");
    sceneFile(dir, "<bsdf type=\"twosided\" id=\"t\">\n<bsdf type=\"bumpmap\"><texture type=\"checkerboard\"/><bsdf "
                   "type=\"diffuse\"/></bsdf></bsdf>");
    CHECK_THAT(errorOf(f), Equals(f + ":3: <bsdf type=\"bumpmap\">: a bumpmap must be the outermost BSDF of its shapes "
                                      "(lt tilts the surface's shading frame)"));
    sceneFile(dir, "<bsdf type=\"bumpmap\" id=\"b\">\n<bsdf type=\"diffuse\"/></bsdf>");
    CHECK_THAT(errorOf(f),
               Equals(f + ":2: <bsdf type=\"bumpmap\" id=\"b\">: bumpmap takes one displacement texture and "
                          "one nested BSDF"));
}

TEST_CASE("the sensor: film, crop, filters, sampler and integrator defaults", "[loader]") {
    test::TempDir dir;
    const auto s = loadScene(sceneFile(dir, R"(
        <integrator type="bdpt"><integer name="maxDepth" value="5"/><integer name="rrDepth" value="3"/>
            <boolean name="lightImage" value="true"/></integrator>
        <sensor type="perspective"><float name="fov" value="40"/><string name="fovAxis" value="y"/>
            <sampler type="ldsampler"><integer name="sampleCount" value="32"/></sampler>
            <film type="hdrfilm"><integer name="width" value="64"/><integer name="height" value="32"/>
                <integer name="cropOffsetX" value="8"/><integer name="cropWidth" value="16"/>
                <rfilter type="gaussian"><float name="stddev" value="0.25"/></rfilter></film></sensor>)"));
    CHECK(s->integrator.maxDepth == 5);
    CHECK(s->integrator.rrDepth == 3);
    CHECK(s->integrator.sampleCount == 32);
    CHECK(s->camera.film().cropX == 8);
    CHECK(s->camera.film().cropWidth == 16);
    CHECK(s->camera.film().cropHeight == 32);
    CHECK(s->camera.film().filter.radius == Approx(1.0));
    // fov 40 along y on a 2:1 film: the horizontal fov is 2 atan(2 tan 20deg).
    CHECK(s->camera.fovX() == Approx(radToDeg(2 * std::atan(2 * std::tan(degToRad(20))))));
    CHECK(std::find(s->ignoredHints.begin(), s->ignoredHints.end(), "integrator bdpt: lightImage") != s->ignoredHints.end());
    // Mitsuba's direct integrator: emitters seen directly and single scattering, paths of two edges.
    CHECK(loadScene(
              sceneFile(dir, R"(<integrator type="direct"><integer name="emitterSamples" value="4"/></integrator>)"))
              ->integrator.maxDepth == 2);
}

TEST_CASE("the thinlens sensor: aperture radius, focus distance (farClip by default), 0 a pinhole",
          "[loader][thinlens]") {
    test::TempDir dir;
    auto sensor = [&](const std::string& props) {
        return sceneFile(dir, "<sensor type=\"thinlens\">\n<float name=\"fov\" value=\"40\"/>" + props + "</sensor>");
    };
    const auto a =
        loadScene(sensor(R"(<float name="apertureRadius" value="0.05"/><float name="focusDistance" value="3"/>)"), {},
                  UnknownProperties::Fail);
    CHECK(a->camera.hasAperture());
    CHECK(a->camera.lens().apertureRadius == 0.05);
    CHECK(a->camera.lens().focusDistance == 3);
    const auto b = loadScene(sensor(R"(<float name="apertureRadius" value="0.05"/><float name="farClip" value="70"/>)"),
                             {}, UnknownProperties::Fail);
    CHECK(b->camera.lens().focusDistance == 70);
    const auto c = loadScene(sensor(R"(<float name="apertureRadius" value="0.05"/>)"));
    CHECK(c->camera.lens().focusDistance == 1e4);
    const auto pinhole = loadScene(sensor(R"(<float name="apertureRadius" value="0"/>)"));
    CHECK_FALSE(pinhole->camera.hasAperture());
    const std::string f = dir.file("scene.xml");
    sensor("");
    CHECK_THAT(errorOf(f), Equals(f + ":2: <sensor type=\"thinlens\">: a thinlens sensor needs apertureRadius"));
    sensor(R"(<float name="apertureRadius" value="0.1"/><float name="focusDistance" value="-2"/>)");
    CHECK_THAT(errorOf(f), Equals(f + ":2: <sensor type=\"thinlens\">: focusDistance must be finite and > 0"));
    // Every projective camera of Mitsuba reads focusDistance (0.6 sensor.cpp): a pinhole's is a hint, not a warning.
    const auto p =
        loadScene(sceneFile(dir, R"(<sensor type="perspective"><float name="focusDistance" value="3"/></sensor>)"), {},
                  UnknownProperties::Fail);
    CHECK(std::find(p->ignoredHints.begin(), p->ignoredHints.end(), "sensor perspective: focusDistance") !=
          p->ignoredHints.end());
}

TEST_CASE("bad input: one clear error line naming file, line and element", "[loader]") {
    test::TempDir dir;
    const std::string f = dir.file("scene.xml");
    SECTION("missing scene file") {
        CHECK_THAT(errorOf(dir.file("nope.xml")), Equals(dir.file("nope.xml") + ": cannot open scene file"));
    }
    SECTION("malformed XML") {
        sceneFile(dir, "<shape type=\"cube\">\n<float name=\"x\" value=\"1\">\n</shape>");
        CHECK_THAT(errorOf(f), StartsWith(f + ":") && Contains("malformed XML"));
    }
    SECTION("bad number") {
        sceneFile(dir, "<shape type=\"sphere\">\n<float name=\"radius\" value=\"1.2.3\"/>\n</shape>");
        CHECK_THAT(errorOf(f), Equals(f + ":3: <float>: '1.2.3' is not a number"));
    }
    SECTION("unknown shape plugin") {
        sceneFile(dir, "<shape type=\"teapot\"/>");
        CHECK_THAT(errorOf(f), Equals(f + ":2: <shape type=\"teapot\">: unknown shape type (lt reads obj, ply, "
                                          "serialized, rectangle, cube, sphere, disk, shapegroup, instance)"));
    }
    SECTION("unknown BSDF plugin") {
        sceneFile(dir, "<bsdf type=\"velvet\" id=\"v\"/>");
        CHECK_THAT(errorOf(f), StartsWith(f + ":2: <bsdf type=\"velvet\" id=\"v\">: unknown BSDF type"));
    }
    SECTION("a property lt does not read, with --strict") {
        sceneFile(dir, "<shape type=\"sphere\">\n<float name=\"radiuss\" value=\"1\"/>\n</shape>");
        CHECK_THAT(test::errorOf([&] { (void)loadScene(f, {}, UnknownProperties::Fail); }),
                   Equals(f + ":3: <shape type=\"sphere\"> does not read the property 'radiuss' (an error with "
                              "--strict; without it lt warns and ignores it, as Mitsuba 0.6 does)"));
    }
    SECTION("property of the wrong type") {
        sceneFile(dir, "<shape type=\"sphere\">\n<string name=\"radius\" value=\"big\"/>\n</shape>");
        CHECK_THAT(errorOf(f), Equals(f + ":3: property 'radius' of <shape type=\"sphere\"> must be float or integer, "
                                          "not string"));
    }
    SECTION("undefined reference") {
        sceneFile(dir, "<shape type=\"cube\">\n<ref id=\"nothing\"/>\n</shape>");
        CHECK_THAT(errorOf(f), Equals(f + ":3: <ref>: reference to undefined id 'nothing'"));
    }
    SECTION("undefined parameter") {
        sceneFile(dir, "<shape type=\"sphere\">\n<float name=\"radius\" value=\"$size\"/>\n</shape>");
        CHECK_THAT(errorOf(f), Equals(f + ":3: <float>: undefined parameter '$size' (give it with <default> or on "
                                          "the command line)"));
    }
    SECTION("unknown element") {
        sceneFile(dir, "<teapot/>");
        CHECK_THAT(errorOf(f), Equals(f + ":2: <teapot>: unknown element"));
    }
    SECTION("participating media are refused by name") {
        sceneFile(dir, "<medium type=\"homogeneous\"/>");
        CHECK_THAT(errorOf(f), Contains("not supported by lt"));
    }
    SECTION("missing mesh") {
        sceneFile(dir, "<shape type=\"obj\">\n<string name=\"filename\" value=\"gone.obj\"/>\n</shape>");
        CHECK_THAT(errorOf(f), Equals(f + ":2: <shape type=\"obj\">: file not found: " + dir.file("gone.obj")));
    }
    SECTION("mesh with NaN") {
        dir.write("nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n");
        sceneFile(dir, "<shape type=\"obj\">\n<string name=\"filename\" value=\"nan.obj\"/>\n</shape>");
        const std::string e = errorOf(f);
        CHECK_THAT(e, StartsWith(f + ":2: <shape type=\"obj\">: " + dir.file("nan.obj") + ":"));
        CHECK_THAT(e, Contains("non-finite"));
    }
    SECTION("degenerate triangles are removed and reported") {
        dir.write("deg.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\n");
        sceneFile(dir, "<shape type=\"obj\">\n<string name=\"filename\" value=\"deg.obj\"/>\n</shape>");
        const auto s = loadScene(f);
        REQUIRE(s->warnings.size() == 1);
        CHECK_THAT(s->warnings[0], Equals(f + ":2: <shape type=\"obj\">: removed 1 degenerate triangle(s)"));
        CHECK(s->shapes[0].mesh().triangles.size() == 1);
    }
    SECTION("unreadable texture") {
        dir.write("tex.png", "this is not a png");
        sceneFile(dir, "<bsdf type=\"diffuse\">\n<texture type=\"bitmap\" name=\"reflectance\">\n"
                       "<string name=\"filename\" value=\"tex.png\"/>\n</texture>\n</bsdf>");
        CHECK_THAT(errorOf(f), StartsWith(f + ":3: <texture type=\"bitmap\">: " + dir.file("tex.png")));
    }
    SECTION("elements nested 100 000 deep (the probe's crash: the parser's recursion ran off the stack)") {
        std::string body;
        for (int i = 0; i < 100000; ++i)
            body += "<bsdf type=\"twosided\">";
        for (int i = 0; i < 100000; ++i)
            body += "</bsdf>";
        sceneFile(dir, body);
        CHECK_THAT(errorOf(f), Equals(f + ":2: <bsdf>: elements nested deeper than 64 levels"));
    }
    SECTION("area emitter outside a shape") {
        sceneFile(dir, "<emitter type=\"area\"/>");
        CHECK_THAT(errorOf(f), Equals(f + ":2: <emitter type=\"area\">: an area emitter must be nested inside a <shape>"));
    }
    SECTION("unknown conductor material lists the known ones") {
        sceneFile(dir, "<bsdf type=\"conductor\">\n<string name=\"material\" value=\"Unobtainium\"/>\n</bsdf>");
        CHECK_THAT(errorOf(f), StartsWith(f + ":2: <bsdf type=\"conductor\">: unknown conductor material 'Unobtainium' (known: ") &&
                                   Contains("Cu"));
    }
    SECTION("singular transform") {
        sceneFile(dir, "<shape type=\"cube\">\n<transform name=\"toWorld\">\n<matrix value=\"0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 1\"/>"
                       "\n</transform>\n</shape>");
        CHECK_THAT(errorOf(f), Equals(f + ":4: <matrix>: transform matrix is singular"));
    }
    SECTION("include cycle") {
        dir.write("a.xml", "<scene version=\"0.5.0\"><include filename=\"scene.xml\"/></scene>");
        sceneFile(dir, "<include filename=\"a.xml\"/>");
        CHECK_THAT(errorOf(f), Equals(f + ": include cycle"));
    }
}
