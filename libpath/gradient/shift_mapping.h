// The shift mapping of gradient-domain path tracing (Kettunen et al. 2015, Sec. 5, after Lehtinen et al.
// 2013): a base path of one pixel moved to another pixel's primary hit, vertex by vertex. The one
// implementation behind G-PT's four neighbours and [GDPR]'s reuse function R (Sec. 3.1: the same shift
// "from primary hit to primary hit"), so a two-pixel tile of path reusing is G-PT.
//
// At every base vertex x_i the offset vertex y_i must be classified alike (gradient/base_path.h
// connectableLobe), else the shift fails. Then:
// * reconnection: when x_i, y_i and x_{i+1} are connectable, y_i connects to x_{i+1} (a shadow ray) and
//   the offset shares the base path's tail (reconnectionJacobian below);
// * half-vector copy: otherwise the base's generalized half vector at x_i (bsdf/half_vector.h), in x_i's
//   shading frame, is applied at y_i to the offset's incident direction, and the ray traced (copyHalfVector
//   below). Total internal reflection, an incident direction on the other side, or a direction that leaves
//   the lobe's hemisphere fail the shift.
// The rule is applied to each ending of the path (the sub-path that ends with the light sample at x_i, or
// with the BSDF sample leaving x_i), because a vertex can be a reconnection target for one ending and not for
// another (a plastic vertex whose base path took the delta coat is not connectable, its light sample is). The
// last segment of an ending leaving a non-delta lobe always reconnects to its end (the light sample's point
// on the light, or what the BSDF sample reached), as the public G-PT code does for light samples: a path that
// reaches a light is then shifted alike whichever of the two techniques sampled it.
//
// The estimators combine a path's techniques by the balance heuristic over "sampled in this pixel" and
// "sampled in pixel m and shifted here" (Kettunen et al. 2015, Eq. 8, extended to a tile as [GDPR] Eq. 6-8),
// with the path tracer's two strategies (light sample, BSDF sample) inside each. A technique's density
// includes its own Russian roulette and is zero where it cannot produce the path, so the weights sum to one
// over the techniques that can ([GDPR] Sec. 3.1); tests/gradient_test.cpp T-GR-2 and T-GR-3 check it.
#pragma once

#include <array>
#include <vector>

#include "gradient/base_path.h"

namespace lt {

// The four neighbours a path is shifted to by G-PT and gradient-domain MLT, in this order: +x, -x, +y, -y.
inline constexpr std::array<std::array<int, 2>, 4> NeighbourOffsets{{{1, 0}, {-1, 0}, {0, 1}, {0, -1}}};

// One ending of a base path, for one pixel: the path's value in that pixel (shifted there, times the
// Jacobian) and its technique density (light sample + BSDF sample, times the Jacobian), both divided by
// the density with which the base path sampled this ending. The balance heuristic over a set of pixels then
// credits pixel m with value_m / sum of density. Ending 2i is the light sample at x_i, ending 2i + 1 the BSDF
// sample leaving x_i (what it hits, or the environment). A failed shift leaves zeros.
struct EndingTerm {
    Spectrum value;
    double density = 0;
};

// Why a shift stopped following the base path.
enum class ShiftCause : int {
    Reconnected,  // joined the base path (reconnectDepth says where)
    Followed,     // followed half vectors to the base path's end without a reconnection
    NoPrimaryHit, // the offset's camera ray left the scene
    Mismatch,     // a vertex classified differently, or a missing lobe or BSDF
    Occluded,     // the reconnection's shadow ray was blocked
    Refraction,   // total internal reflection, or the half-vector copy left the lobe's hemisphere
    Escaped,      // the offset's ray left the scene (or hit something) where the base path's did not
    EarlyOut,     // stopped where it would rejoin a base path that carries no light after that vertex
    Count
};

struct ShiftOutcome {
    ShiftCause cause = ShiftCause::Followed;
    int reconnectDepth = 0; // vertex index i of the reconnection y_i -> x_{i+1} (1 = the primary hit)
};

// The terms of a base path for its own pixel (value: the path tracer's estimate of each ending).
[[nodiscard]] std::vector<EndingTerm> baseEndingTerms(const Scene& scene, const BasePath& base);

// [GDPR] Sec. 3.3's early out. Every shift that gets past the base path's first reconnection vertex x_i (x_i
// connectable, and x_{i+1} joinable or none) rejoins the base path there and shares its tail; the endings from
// x_i's BSDF sample on carry light only through that tail: an emitter at x_{i+1} or beyond (its radiance toward
// the offset may differ: any emitter counts), the environment along x_i's escape direction (the offset's
// too), the base's light samples after x_i with their visibility. When none can, the shift stops at x_i after
// its light sample, and the rest of its endings are zero. This is exact: an ending that carries light in no
// pixel of the set adds nothing, whatever its densities (shareOverPixels). (Unless a term there would not be
// finite, e.g. an overflowing Jacobian times a zero radiance: followed to its end, the shift would drop the
// whole base path as non-finite; with the early out that term is never computed and the path counts.)
// A shift that reaches x_i and is classified there as the base is counts as early_out, with x_i as its
// reconnection depth.
enum class EarlyOut {
    Take,
    Never // follow every shift to its end (the tests compare both)
};

// Shifts `base` onto the offset primary vertex `offset` (another pixel's primary hit, or nothing when that
// pixel's camera ray escapes) and writes its terms, one per ending of `base`, into `out`: zeros for the
// endings the shift cannot reach. An ending whose path one technique cannot produce (a blocked reconnection
// cannot be a BSDF sample's) counts only the techniques that can.
ShiftOutcome shiftBasePath(const Scene& scene, const BasePath& base, const std::optional<BaseVertex>& offset,
                           double shiftThreshold, std::vector<EndingTerm>& out, EarlyOut earlyOut = EarlyOut::Take);

// The Jacobian of a reconnection to surface point z (geometric normal n): the solid
// angle at `offset` over the solid angle at `base` of the directions toward the area around z, |cos theta'| /
// |offset - z|^2 over |cos theta| / |base - z|^2 (Kettunen et al. 2015, Eq. 11). 0 when the base direction
// grazes z (no density in solid angle) or the ratio is not finite: then the ending has no offset technique.
[[nodiscard]] double reconnectionJacobian(const Vec3& offset, const Vec3& base, const Vec3& z, const Vec3& n);

// The half-vector copy at the offset vertex y (its incident direction y.wi): the direction leaving y whose
// generalized half vector, in y's shading frame, is that of (wiX, woX) at x in x's frame; y's f_s |cos| and
// density there (for a delta lobe: weight x probability and probability, from deltaEval), and the Jacobian
// d omega_y / d omega_x. Nothing on total internal reflection, an incident direction on the other side of
// the surface, a direction outside the lobe's hemisphere, or a delta lobe y does not have.
struct HalfVectorCopy {
    Vec3 wo;
    Spectrum fCos;
    double pdf = 0;
    double jacobian = 1;
};
[[nodiscard]] std::optional<HalfVectorCopy> copyHalfVector(const BaseVertex& x, const Vec3& wiX, const Vec3& woX,
                                                           bool deltaLobe, const BaseVertex& y);

// The balance heuristic over a set of pixels for one base path ([GDPR] Eq. 7 with the exact balance
// weights, the shift Jacobians included; for two pixels Kettunen et al. 2015, Eq. 8): terms[m] holds the
// path's ending terms in pixel m (baseEndingTerms for its own pixel, shiftBasePath for the others). Adds to
// share[m] pixel m's part of every ending, value_m / sum over the set of density. A pixel outside the set is a
// technique that does not exist. Returns false, adding nothing, when a share is not finite.
bool shareOverPixels(const std::vector<const std::vector<EndingTerm>*>& terms, std::vector<Spectrum>& share);

} // namespace lt
