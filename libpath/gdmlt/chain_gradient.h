// Gradient-domain estimates from the states of path-space Markov chains (Lehtinen et al. 2013, gradient-domain
// MLT, Sec. 4): every state x is shifted to its four neighbouring pixels with the one shift mapping of G-PT
// (gradient/shift_mapping.h), and the pairs (x, T_k x) give the primal image and the forward differences.
//
// The estimator. A chain with target f* visits x with density p(x) = f*(x) / b over the image (b the integral of
// f*), and its N mutations credit the states (expected values: mcmc/metropolis.h), so (b / N) sum credit g(x) /
// f*(x) estimates the integral of g. Take g the pair's contribution: f(x) at x's raster position r and
// F_k(x) = f(T_k x) |T_k'| at r + k (the shifted path's contribution in x's measure). The pair (x, T_k x) is
// produced by two techniques: x drawn by the chain (density p(x)), or T_k x drawn and shifted back by T_-k =
// T_k^-1 (density p(T_k x) |T_k'| in x's measure). Weights w_A(x) + w_B(T_k x) = 1 for every pair make the sum
// over both unbiased; with any positive function g*,
//   w(x) = g*(x) / (g*(x) + g*(T_k x) |T_k'|)
// has that property (from T_k x's side the same formula gives g*(T_k x) |T_k'| / (same)). The balance heuristic
// of the chain's densities is g* = f*. lt takes g* = lum f (mcmc/image_contribution.h targetValue): the balance
// heuristic exactly when the chain targets luminance, and for the gradient target below a weight that is zero
// whenever f(x) = 0. That matters: a path-space chain never visits a path that carries nothing (an occluded path
// is rejected), so the technique "x drawn by the chain" must not be needed where f(x) = 0, and with this w the
// pair is then credited wholly to T_k x's own draws. Both pair members get the pair's weight (Kettunen et al.
// 2015, Eq. 8, with p the chain's density): pixel j receives w f(x), pixel j + k receives w F_k(x), and the
// difference I_{j+k} - I_j receives w (F_k - f), each times (b / N) credit / f*(x). A state contributes to its
// own pixel through all four pairs, so each pair's primal parts count a quarter (the four weights of a path
// across the directions k and -k sum to two, over all four to four). A neighbour off the sensor (where no
// chain draws a state, mcmc/sensor_window.h; not the crop: the pair's two sides must agree) has no technique: w = 1.
// Emitters seen directly (two-vertex paths) go to the "direct" plane, unshifted.
//
// F_k from the shift mapping. The state is written as a base path with one ending, the light it reaches (a
// BSDF sample's ending; a light sample's for point, spot and directional lights, which no BSDF sample reaches),
// with densities 1 and no Russian roulette: the shift's value for that ending over the base's own value is then
// f(T_k x) |T_k'| / f(x) in the base path's measure, and the same ratio in any measure (the measure conversions
// cancel), so F_k = f(x) x that ratio.
#pragma once

#include <array>
#include <vector>

#include "formats/records.h"
#include "gradient/gradient_settings.h"
#include "image/film.h"
#include "mcmc/markov_path.h"
#include "mcmc/sensor_window.h"
#include "path/vertex.h"

namespace lt {

class Scene;

// A state's contributions in its four neighbours (NeighbourOffsets' order, gradient/shift_mapping.h): F[k] = f(T_k x)
// |T_k'| (zero where the shift fails), and whether the neighbour's raster position lies where the sensor responds
// (mcmc/sensor_window.h: the crop grown by the filter's margin, where the chains draw their states; else no chain can
// draw T_k x and no pair is formed).
struct ChainShifts {
    std::array<Spectrum, 4> F;
    std::array<bool, 4> onFilm{};
};

// Shifts the path v (light to eye, at least one scattering vertex; contribution f at raster position `raster`)
// to its four neighbours. `shiftThreshold`: gradient/base_path.h connectableLobe. `stats` (may be null) counts
// the shifts' outcomes. A path whose own value the base-path form cannot reproduce (zero there) shifts nowhere.
[[nodiscard]] ChainShifts shiftChainState(const Scene& scene, const SensorWindow& sensor,
                                          const std::vector<PathVertex>& v, const Vec2& raster, const Spectrum& f,
                                          double shiftThreshold, ShiftStatistics* stats);

// GDMLT's target (Lehtinen et al. 2013, Sec. 5; the survey's Eq. 29 summed over the four pairs), so that chains
// spend their time where the gradients are: f* = sum_k lum|F_k - f| + alpha targetValue(f) over the neighbours on
// the film, positive wherever f is not black. An emitter seen directly (two vertices) is not shifted (its light
// goes to the "direct" plane, estimated in the image domain) and keeps the luminance target, targetValue(f).
[[nodiscard]] PathTarget gradientTarget(const Scene& scene, double alpha, double shiftThreshold);

// One state's splats, not yet scaled by b / N: the film's planes. Splat values carry credit / (f* pixels), as
// the chains' own image (mcmc/metropolis.h ChainImage).
struct ChainGradientSplats {
    std::vector<Splat> primal, dx, dy, direct;
    void clear() {
        primal.clear();
        dx.clear();
        dy.clear();
        direct.clear();
    }
};

// Adds the splats of one streamed state (file::ChainState). Returns false, adding nothing, when a value is not
// finite; throws lt::Error ("a chain state ...") when the state lies off the film or does not re-create in the
// scene.
bool addChainState(const Scene& scene, const PixelRect& window, const file::ChainState& state, double shiftThreshold,
                   ChainGradientSplats& out, ShiftStatistics* stats);

} // namespace lt
