// What the point-like emitters (point, spot) share: the direct sample toward a reference point is the
// emitter's one position, chosen with discrete probability 1; the caller fills in the arriving value,
// intensity toward the reference over the squared distance (pbrt-v3 PointLight, SpotLight).
#pragma once

#include "scene/emitter.h"

namespace lt {

// The sample without its value; nothing (pdf 0) when ref coincides with the position.
inline DirectSample pointSourceSample(const Vec3& position, const Vec3& ref) {
    DirectSample ds;
    const Vec3 v = position - ref;
    ds.dist = length(v);
    if (!(ds.dist > 0)) return {};
    ds.p = position;
    ds.wi = v / ds.dist;
    ds.pdf = 1;
    return ds;
}

} // namespace lt
