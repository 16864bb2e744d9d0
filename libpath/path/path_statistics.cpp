#include "path/path_statistics.h"

namespace lt {

PathStatistics pathStatistics(std::span<const file::PathRecord> paths) {
    PathStatistics s;
    s.count = paths.size();
    for (const auto& p : paths) {
        // Edges, not vertices: the "path length" of Veach and of maxDepth (Mitsuba's meaning).
        ++s.lengths[p.vertices.empty() ? 0 : p.vertices.size() - 1];
        ++s.techniques[{p.s, p.t}];
        s.weight.add(p.weight);
    }
    return s;
}

} // namespace lt
