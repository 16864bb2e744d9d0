// Multiple importance sampling weights (Veach thesis ch. 9). The one place for the heuristics: BDPT's
// ratio recursion and the path tracer's two-strategy weights both call these.
#pragma once


namespace lt {

enum class MisHeuristic { Power, Balance };

// The heuristic applied to a density ratio r = p_other / p_this (balance: r, power with beta = 2: r^2).
inline double misHeuristic(MisHeuristic h, double r) { return h == MisHeuristic::Power ? r * r : r; }

// Weight of a strategy with density pa against one other with density pb.
inline double misWeight2(MisHeuristic h, double pa, double pb) {
    if (!(pa > 0)) return 0;
    return 1.0 / (1.0 + misHeuristic(h, pb / pa));
}

} // namespace lt
