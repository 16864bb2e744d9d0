// The lens point of a camera sample (scene/camera.h): a thin lens's from the next two numbers of the
// sampler, the pinhole without drawing any, so that a pinhole's samples stay as they were.
#pragma once

#include "sampling/sample_generator.h"
#include "scene/camera.h"

namespace lt {

inline Vec3 sampleLensPoint(const PerspectiveCamera& camera, SampleGenerator& sampler) {
    return camera.hasAperture() ? camera.sampleLens(sampler.next2D()) : camera.position();
}

} // namespace lt
