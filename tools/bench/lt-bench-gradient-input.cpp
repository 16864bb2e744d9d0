// lt-bench-gradient-input: a synthetic gradient-domain render for benchmarking lt-reconstruct: a known
// RGB image (smooth ramps, discs and bars with sharp edges), its primal and forward-difference gradients
// with Gaussian noise, and optionally sparse huge outliers in the gradients (fireflies). Writes an lt
// buffer file with primal.R/G/B, dx.R/G/B, dy.R/G/B and, with --truth, the noise-free image as EXR.
#include <CLI/CLI.hpp>

#include <cmath>
#include <iostream>

#include "common/tool.h"
#include "formats/ltfile.h"
#include "image/image_io.h"
#include "math/rng.h"
#include "reconstruct/gradient_image.h"

int main(int argc, char** argv) {
    CLI::App app{"lt-bench-gradient-input: a synthetic noisy primal and gradients (lt buffer file) for lt-reconstruct",
                 "lt-bench-gradient-input"};
    uint32_t width = 1280, height = 720;
    double noise = 0.1, gradientNoise = 0.02, outliers = 0, outlierValue = 1e3;
    uint64_t seed = 1;
    std::string out, truthOut;
    app.add_option("--width", width, "pixels (default 1280)")->check(CLI::PositiveNumber);
    app.add_option("--height", height, "pixels (default 720)")->check(CLI::PositiveNumber);
    app.add_option("--noise", noise, "standard deviation of the primal noise (default 0.1)");
    app.add_option("--gradient-noise", gradientNoise, "standard deviation of the gradient noise (default 0.02)");
    app.add_option("--outliers", outliers, "fraction of gradient values replaced by +-outlier-value (default 0)");
    app.add_option("--outlier-value", outlierValue, "magnitude of the outliers (default 1000)");
    app.add_option("--seed", seed, "random seed (default 1)");
    app.add_option("-o,--output", out, "lt buffer file to write")->required();
    app.add_option("--truth", truthOut, "noise-free image to write (EXR)");
    return lt::tool::run(app, argc, argv, [&] {
        const size_t N = size_t(width) * height;
        lt::RgbPlanes truth;
        for (size_t c = 0; c < 3; ++c)
            truth[c].resize(N);
        for (uint32_t y = 0; y < height; ++y)
            for (uint32_t x = 0; x < width; ++x) {
                const double u = (x + 0.5) / width, v = (y + 0.5) / height;
                double rgb[3] = {0.2 + 0.3 * u, 0.3 + 0.2 * v, 0.25 + 0.1 * std::sin(6 * u + 4 * v)};
                const double d = std::hypot(u - 0.3, v - 0.5);
                if (d < 0.2) rgb[0] += 2.0, rgb[1] += 1.5; // a bright disc: sharp edges
                if (u > 0.6 && u < 0.65) rgb[2] += 1.0;    // a vertical bar
                if (v > 0.8 && v < 0.82) rgb[1] += 0.5;    // a horizontal bar
                for (size_t c = 0; c < 3; ++c)
                    truth[c][size_t(y) * width + x] = float(rgb[c]);
            }
        lt::RgbPlanes dx, dy;
        lt::forwardDifferences(truth, width, height, dx, dy);
        lt::Pcg32 rng(seed, 7);
        lt::RgbPlanes primal = truth;
        for (size_t c = 0; c < 3; ++c)
            for (size_t p = 0; p < N; ++p) {
                primal[c][p] += float(noise * lt::standardNormal(rng));
                dx[c][p] += float(gradientNoise * lt::standardNormal(rng));
                dy[c][p] += float(gradientNoise * lt::standardNormal(rng));
                if (outliers > 0 && rng.nextDouble() < outliers)
                    (rng.nextDouble() < 0.5 ? dx : dy)[c][p] =
                        float(rng.nextDouble() < 0.5 ? -outlierValue : outlierValue);
            }
        lt::file::Buffer buffer;
        buffer.width = width;
        buffer.height = height;
        const char* rgb[3] = {"R", "G", "B"};
        for (const auto& [layer, planes] : {std::pair{"primal", &primal}, std::pair{"dx", &dx}, std::pair{"dy", &dy}})
            for (size_t c = 0; c < 3; ++c) {
                buffer.channels.push_back(std::string(layer) + "." + rgb[c]);
                buffer.planes.push_back((*planes)[c]);
            }
        const nlohmann::json info{{"producer", "lt-bench-gradient-input"},
                                  {"parameters",
                                   {{"width", width},
                                    {"height", height},
                                    {"noise", noise},
                                    {"gradient_noise", gradientNoise},
                                    {"outliers", outliers},
                                    {"seed", seed}}}};
        lt::file::Writer writer(out, lt::file::FileKind::Buffer, info);
        writer.writeBuffer(buffer);
        writer.finish();
        if (!truthOut.empty()) lt::writeExr(truthOut, lt::rgbBuffer(width, height, std::move(truth)), info);
        return 0;
    });
}
