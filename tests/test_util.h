// Helpers shared by the tests: temporary directories and files, paths of the shipped scenes.
#pragma once

#include <catch2/catch.hpp>
#include <unistd.h>

#include <filesystem>
#include <functional>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>

#include "sampling/bdpt.h"
#include "sampling/path_tracer.h"
#include "util/error.h"

namespace lt::test {

// lt-seed's two pixel estimators, made with the path settings as given (MIS heuristic included), for tests that
// render with both.
enum class PixelMethod { Bdpt, PathTracing };
inline std::unique_ptr<PixelEstimator> makePixelEstimator(PixelMethod method, const Scene& scene,
                                                          const PathSettings& paths) {
    if (method == PixelMethod::PathTracing) return std::make_unique<PathTracer>(scene, paths);
    return std::make_unique<Bdpt>(scene, paths);
}

// A fresh directory under the system temp dir, removed with everything in it at scope exit.
struct TempDir {
    std::filesystem::path path;
    TempDir() {
        static int counter = 0;
        path = std::filesystem::temp_directory_path() /
               ("lt_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
        std::filesystem::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    // Write a file (binary, exactly the given bytes) and return its full path.
    std::string write(const std::string& name, const std::string& contents) const {
        const auto p = path / name;
        std::filesystem::create_directories(p.parent_path());
        std::ofstream(p, std::ios::binary) << contents;
        return p.string();
    }
    [[nodiscard]] std::string file(const std::string& name) const { return (path / name).string(); }
};

// A scene of the repository's scenes/ folder, by its folder name.
inline std::string shippedScene(const std::string& name) {
    return std::string(LT_SOURCE_DIR) + "/scenes/" + name + "/scene.xml";
}

// The message of the lt::Error that f throws, or "(no error)".
inline std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "(no error)";
}

// An RGB float EXR of w x h pixels, rows top to bottom (an envmap or a reference for a test).
inline void writeRgbExr(const std::string& filename, int w, int h, const std::vector<float>& rgb) {
    auto out = OIIO::ImageOutput::create(filename);
    REQUIRE(out);
    const OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::FLOAT);
    REQUIRE(out->open(filename, spec));
    REQUIRE(out->write_image(OIIO::TypeDesc::FLOAT, rgb.data()));
    REQUIRE(out->close());
}

// A convex diffuse sphere (radius 1, albedo 0.7) under a uniform sky of radiance 2, seen from 5 away at
// 32 x 32 pixels: every point of the sphere sees only the sky, so it sends 0.7 * 2 = 1.4. The sphere
// subtends 11.5 degrees around the axis: the central 8 x 8 pixels see only the sphere, the 3 x 3 corners
// only the sky.
inline std::string skySphere(const TempDir& dir) {
    return dir.write("sky.xml", R"(<scene version="0.5.0">
  <integrator type="path"><integer name="maxDepth" value="-1"/></integrator>
  <sensor type="perspective"><float name="fov" value="40"/>
    <transform name="toWorld"><lookat origin="0,0,5" target="0,0,0" up="0,1,0"/></transform>
    <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="32"/><rfilter type="box"/></film>
  </sensor>
  <emitter type="constant"><rgb name="radiance" value="2"/></emitter>
  <shape type="sphere"><float name="radius" value="1"/>
    <bsdf type="diffuse"><rgb name="reflectance" value="0.7"/></bsdf></shape>
</scene>)");
}

// A closed box whose walls all emit Le = 1 and reflect diffusely with albedo rho, seen from inside;
// `scale` shrinks the whole scene (the camera's near clip with it), `filter` picks the pixel filter;
// `inside`: more shapes in the box (lossless specular ones keep every pixel at Le * sum of rho^k).
inline std::string furnaceBox(const TempDir& dir, double rho, int maxDepth, const std::string& filter = "box",
                              double scale = 1, const std::string& inside = "") {
    const std::string s = std::to_string(scale);
    return dir.write("furnace.xml", R"(<scene version="0.5.0">
  <integrator type="path"><integer name="maxDepth" value=")" +
                                        std::to_string(maxDepth) + R"("/></integrator>
  <sensor type="perspective"><float name="fov" value="60"/><float name="nearClip" value=")" +
                                        std::to_string(1e-3 * scale) + R"("/>
    <transform name="toWorld"><lookat origin=")" +
                                        std::to_string(0.1 * scale) + "," + std::to_string(0.2 * scale) + "," +
                                        std::to_string(0.3 * scale) + R"(" target="1,0.5,-2" up="0,1,0"/></transform>
    <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="24"/><rfilter type=")" +
                                        filter + R"("/></film>
  </sensor>
  <shape type="cube"><boolean name="flipNormals" value="true"/><transform name="toWorld"><scale value=")" +
                                        s + R"("/></transform>
    <bsdf type="diffuse"><rgb name="reflectance" value=")" +
                                        std::to_string(rho) + R"("/></bsdf>
    <emitter type="area"><rgb name="radiance" value="1"/></emitter>
  </shape>
)" + inside + R"(
</scene>)");
}

// A glass ball over a diffuse floor lit by a small sphere lamp, every length multiplied by `scale`: the
// caustic beside the ball is a walk of floor -> glass -> glass -> lamp. `eyeHeight` puts the camera
// that high over the floor, 2.5 away (0.01: the floor seen at 89.8 degrees from its normal). A positive
// `alpha` frosts the ball (roughdielectric, Beckmann): its chains are glossy.
inline std::string ballScene(const TempDir& dir, double ior, double scale, double eyeHeight, double alpha = 0) {
    const auto n = [&](double v) {
        std::ostringstream s;
        s.precision(17);
        s << v * scale;
        return s.str();
    };
    std::ostringstream xml;
    xml.precision(17);
    xml << R"(<scene version="0.5.0">
  <sensor type="perspective"><float name="fov" value="50"/><float name="nearClip" value=")"
        << n(0.01) << R"("/>
    <transform name="toWorld"><lookat origin="0,)"
        << n(eyeHeight) << "," << n(2.5) << R"(" target="0,)" << n(0.2) << R"(,0" up="0,1,0"/></transform>
    <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="32"/></film>
  </sensor>
  <shape type="rectangle"><transform name="toWorld"><scale value=")"
        << n(3) << R"("/><rotate x="1" angle="-90"/></transform>
    <bsdf type="diffuse"/></shape>
  <shape type="sphere"><point name="center" x="0" y=")"
        << n(0.3) << R"(" z="0"/><float name="radius" value=")" << n(0.3) << R"("/>
    <bsdf type=")"
        << (alpha > 0 ? "roughdielectric" : "dielectric") << R"("><float name="intIOR" value=")" << ior
        << R"("/><float name="extIOR" value="1"/>)";
    if (alpha > 0)
        xml << R"(<float name="alpha" value=")" << alpha << R"("/><string name="distribution" value="beckmann"/>)";
    xml << R"(</bsdf></shape>
  <shape type="sphere"><point name="center" x=")"
        << n(1) << R"(" y=")" << n(0.6) << R"(" z="0"/><float name="radius" value=")" << n(0.02) << R"("/>
    <emitter type="area"><rgb name="radiance" value=")"
        << 100 / (scale * scale) << R"("/></emitter></shape>
</scene>)";
    return dir.write("ball.xml", xml.str());
}

} // namespace lt::test
