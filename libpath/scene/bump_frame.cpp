#include "scene/bump_frame.h"

namespace lt {

void applyBumpMap(SurfaceInteraction& si, const Texture& displacement) {
    const Vec2 grad = displacement.luminanceGradient(si.uv);
    const Vec3& n = si.shading.n;
    const Vec3 dpdu = si.dpdu + n * (grad.x - dot(n, si.dpdu));
    const Vec3 dpdv = si.dpdv + n * (grad.y - dot(n, si.dpdv));
    Vec3 bumped = cross(dpdu, dpdv);
    const double len = length(bumped);
    // A degenerate parameterization (a pole, a zero-area triangle's uv) leaves the frame as it was.
    if (!(len > 0) || !std::isfinite(len)) return;
    bumped = bumped / len;
    if (dot(bumped, si.ng) < 0) bumped = -bumped;
    si.shading = Frame::fromNormalTangent(bumped, dpdu);
    si.bumped = true;
}

} // namespace lt
