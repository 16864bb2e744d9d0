// The specular chains of stored paths (formats/records.h, light-to-eye order) rebuilt on their scene:
// their generalized geometry terms and walks from each chain to itself, the report of
// `lt-inspect PATHS.ltp --manifold` (useful when a manifold mutation misbehaves).
#pragma once

#include <optional>
#include <ostream>
#include <span>
#include <vector>

#include "formats/records.h"
#include "manifold/manifold_walk.h"
#include "manifold/walk_statistics.h"

namespace lt {

// A maximal run of delta (ideal specular) vertices of a stored path with its two non-delta endpoints.
struct StoredChain {
    size_t first = 0, last = 0;          // endpoint indices in PathRecord::vertices
    ManifoldChain chain;                 // rebuilt with Shape::surfaceAt(prim, coords); empty if that failed
    std::optional<double> G;             // ME Eq. 9
    WalkEnd moving = WalkEnd::Last;      // the end walked: the eye end unless it has no surface
    WalkResult exact;                    // the re-traced chain walked to its own stored endpoint
    std::optional<WalkResult> perturbed; // walk to a nearby point of the same surface, if one was found
    std::optional<WalkResult> reverse;   // the reverse walk of a converged perturbed walk (ME section 5.1)
};

// The chains of one path, rebuilt; paths without delta vertices have none.
[[nodiscard]] std::vector<StoredChain> specularChains(const Scene& scene, const file::PathRecord& path);

// G; the exact walk (the chain re-traced from its pinned end, walked to its stored endpoint; on
// success it replaces c.chain); the perturbed walk (target about `relativeStep` of the scene diagonal away, found
// by a ray from the chain's second-to-last vertex), and the reverse walk; perturbed walks and their
// reversibility go into `stats`.
void checkChain(const Scene& scene, StoredChain& c, WalkStatistics& stats, double relativeStep = 1e-3,
                const WalkSettings& settings = {});

// Per path (the first `listed`): its chains, G and walk outcomes; then the statistics of all paths.
void printManifoldReport(std::ostream& out, const Scene& scene, std::span<const file::PathRecord> paths, size_t listed);

} // namespace lt
