// The specular chains of a path, built in the manifold's charts from its vertices (in memory, or re-created
// from a stored record first): their generalized geometry terms and walks from each chain to itself, and
// the report of `lt-inspect PATHS.ltp --manifold` (useful when a manifold mutation misbehaves).
#pragma once

#include <optional>
#include <ostream>
#include <span>
#include <string>
#include <vector>

#include "formats/records.h"
#include "path/vertex.h"
#include "manifold/manifold_walk.h"
#include "manifold/walk_statistics.h"

namespace lt {

// A maximal run of delta (ideal specular) vertices of a path with its two non-delta endpoints.
struct ChainInPath {
    size_t first = 0, last = 0;          // endpoint indices among the path's vertices
    ManifoldChain chain;                 // in the manifold's charts; empty where a chart is degenerate
    std::optional<double> G;             // ME Eq. 9
    WalkEnd moving = WalkEnd::Last;      // the end walked: the eye end unless it has no surface
    bool walkable = false;               // it has an end with a surface to walk (camera to sky has none)
    WalkResult exact;                    // the re-traced chain walked to its own stored endpoint
    std::optional<WalkResult> perturbed; // walk to a nearby point of the same surface, if one was found
    std::optional<WalkResult> reverse;   // the reverse walk of a converged perturbed walk (ME section 5.1)
};

// The vertices path[from] .. path[to] (either order; `from` first) in the manifold's charts, the
// interior set up by setScattering: delta vertices specular (offset 0), the others holding their
// current offset (glossy vertices treated as specular, ME Sec. 5.2): the chain a walk pinned at `from`
// moves. Nothing where a chart is degenerate or a constraint undefined.
[[nodiscard]] std::optional<ManifoldChain> manifoldChain(std::span<const PathVertex> path, size_t from, size_t to);

// The chains of a path given by its vertices, light to eye (PathVertex::delta marks the specular ones);
// paths without delta vertices have none.
[[nodiscard]] std::vector<ChainInPath> specularChains(std::span<const PathVertex> path);
// The same for a stored path, its vertices re-created first (path/path_record.h verticesFromRecord, which
// throws lt::Error naming `name` when the record does not fit the scene).
[[nodiscard]] std::vector<ChainInPath> specularChains(const Scene& scene, const file::PathRecord& path,
                                                      const std::string& name);

// G; the exact walk (the chain re-traced from its pinned end, walked to its stored endpoint; on
// success it replaces c.chain); the perturbed walk (target about `relativeStep` of the scene diagonal away, found
// by a ray from the chain's second-to-last vertex), and the reverse walk; perturbed walks and their
// reversibility go into `stats`.
void checkChain(const Scene& scene, ChainInPath& c, WalkStatistics& stats, double relativeStep = 1e-3,
                const WalkSettings& settings = {});

// Per path (the first `listed`): its chains, G and walk outcomes; then the statistics of all paths.
void printManifoldReport(std::ostream& out, const Scene& scene, std::span<const file::PathRecord> paths, size_t listed);

} // namespace lt
