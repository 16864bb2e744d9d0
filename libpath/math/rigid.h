// Whether a transform is rigid (rotation or reflection plus translation): the camera and the envmap
// require it, as Mitsuba does ("Scale factors in the camera-to-world transformation are not allowed";
// the envmap's toWorld is "a linear emitter-to-world space rotation"), because their solid-angle
// densities would otherwise need the Jacobian of the linear part.
#pragma once

#include <cmath>

#include "math/transform.h"

namespace lt {

// True when the upper-left 3x3 block M satisfies |M^T M - I| <= tol entrywise. The default tolerance
// accepts matrices printed with six significant digits (the veach-bidir camera deviates by ~1e-5), as
// Mitsuba's own scale check does; the densities then carry a relative error of that order.
inline bool isRigid(const Transform& t, double tol = 1e-3) {
    const auto& m = t.matrix().m;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            const double g = m[0][i] * m[0][j] + m[1][i] * m[1][j] + m[2][i] * m[2][j];
            if (!(std::abs(g - (i == j ? 1.0 : 0.0)) <= tol)) return false;
        }
    return true;
}

} // namespace lt
