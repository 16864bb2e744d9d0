// What the infinite emitters (directional, constant, envmap) share: the scene's bounding sphere, set by
// setSceneBounds, and the emission-position domain of emitter.h, a disk of the bounding-sphere radius
// perpendicular to the direction light travels, placed upstream of the scene so that every ray
// started on it crosses the whole sphere (pbrt-v3 InfiniteAreaLight::Sample_Le).
#pragma once

#include "math/constants.h"
#include "math/frame.h"
#include "math/warp.h"

namespace lt {

struct SceneDisk {
    Vec3 center;
    double radius = 0;

    // A point uniform on the disk for light travelling along d (unit).
    [[nodiscard]] Vec3 sample(const Vec2& u, const Vec3& d) const {
        const Vec2 q = warp::squareToUniformDiskConcentric(u);
        const Frame f = Frame::fromNormal(d);
        return center + (f.s * q.x + f.t * q.y - d) * radius;
    }
    // Area density of sample(): 1 / (pi r^2).
    [[nodiscard]] double pdf() const { return 1.0 / (Pi * radius * radius); }
    [[nodiscard]] double area() const { return Pi * radius * radius; }

    // A point along wi from ref that lies beyond the bounding sphere (the p of a DirectSample of an
    // infinite emitter); the distance reported to callers stays infinite.
    [[nodiscard]] Vec3 beyond(const Vec3& ref, const Vec3& wi) const {
        return ref + wi * (length(ref - center) + 2 * radius);
    }
};

} // namespace lt
