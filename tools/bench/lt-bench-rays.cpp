// lt-bench-rays: the raw incoherent ray rate of a scene's acceleration structure, the bound a renderer on
// that scene cannot beat. Rays start uniformly inside the scene's bounds in uniform directions, as a
// path tracer's bounces do after the first; only closest-hit queries (Embree's rtcIntersect1 plus lt's
// analytic shapes), without computing the differential geometry at the hit. Measured twice: with the
// scene as lt builds it (Embree's robust traversal, which keeps rays grazing shared edges from leaking) and
// with the same BVH built without it, Embree's default (Tungsten's), which is what robustness costs.
#include <CLI/CLI.hpp>

#include <chrono>
#include <iostream>
#include <vector>

#include "common/tool.h"
#include "math/rng.h"
#include "math/warp.h"
#include "sampling/parallel_run.h"
#include "scene/accel.h"
#include "scene/scene.h"

int main(int argc, char** argv) {
    CLI::App app{"lt-bench-rays: closest-hit rays per second on a scene (random origins in its bounds, random "
                 "directions)",
                 "lt-bench-rays"};
    std::string scenePath;
    uint64_t rays = 20000000;
    int threads = 0;
    app.add_option("SCENE", scenePath)->required();
    app.add_option("--rays", rays, "number of rays (default 2e7)");
    app.add_option("--threads", threads, "threads (default: all cores)")->check(lt::tool::ThreadCount);
    return lt::tool::run(app, argc, argv, [&] {
        const auto scene = lt::loadScene(scenePath);
        lt::ParallelRun run(lt::RunControl{threads});
        // The rays are made before the clock starts (1M of them, traced repeatedly), so the rate is that
        // of the traversal alone, not of the random numbers.
        const uint64_t pool = std::min<uint64_t>(rays, 1u << 20);
        std::vector<lt::Ray> batch(pool);
        lt::Pcg32 rng(1, 17);
        const lt::Vec3 lo = scene->bounds.lo, ext = scene->bounds.extent();
        for (auto& r : batch) {
            r.o = lo + lt::Vec3(rng.nextDouble(), rng.nextDouble(), rng.nextDouble()) * ext;
            r.d = lt::warp::squareToUniformSphere({rng.nextDouble(), rng.nextDouble()});
        }
        const uint64_t blocks = 1024, perBlock = rays / blocks;
        const std::vector<bool> include = scene->geometryShapes();
        for (const bool robust : {true, false}) {
            lt::EmbreeAccel accel;
            accel.build(scene->shapes, include, robust);
            std::vector<uint64_t> hitsOf(blocks, 0);
            uint64_t hits = 0;
            const auto start = std::chrono::steady_clock::now();
            run.forEach(
                blocks,
                [&](uint64_t b) {
                    for (uint64_t i = 0; i < perBlock; ++i)
                        if (accel.intersect(batch[(b * perBlock + i) % pool])) ++hitsOf[b];
                },
                [&](uint64_t b) { hits += hitsOf[b]; });
            const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            std::cout << (robust ? "robust (as lt renders): " : "not robust (Embree's default): ") << blocks * perBlock
                      << " rays, " << run.threads() << " threads, " << s
                      << " s: " << double(blocks * perBlock) / s / 1e6 << " M rays/s ("
                      << 100.0 * double(hits) / double(blocks * perBlock) << " % hit)\n";
        }
        return 0;
    });
}
