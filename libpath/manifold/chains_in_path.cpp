#include "manifold/chains_in_path.h"

#include <iomanip>

#include "bsdf/bsdf.h"
#include "manifold/specular_constraint.h"
#include "util/error.h"
#include "path/path_record.h"

namespace lt {

namespace {

// A vertex in the manifold's chart: on its surface, at infinity (environment, directional light), or a
// point (camera, point light) with the chart of the plane facing its neighbour.
std::optional<ManifoldVertex> chartOf(const PathVertex& v, const PathVertex& neighbour) {
    if (v.infinite) return infiniteVertex(v.p(), -v.ng()); // ng: the direction of travel
    if (v.type == VertexType::Camera || !v.isOnSurface() || v.si.shape < 0) {
        const Vec3 d = neighbour.p() - v.p();
        if (!(lengthSquared(d) > 0)) return std::nullopt;
        return pointVertex(v.p(), normalize(d));
    }
    return manifoldVertex(v.si);
}

bool isDelta(const PathVertex& v) { return v.type == VertexType::Surface && v.delta; }

} // namespace

std::optional<ManifoldChain> manifoldChain(std::span<const PathVertex> V, size_t from, size_t to) {
    if (from == to || from >= V.size() || to >= V.size()) return std::nullopt;
    const int step = to > from ? 1 : -1;
    const size_t n = (to > from ? to - from : from - to) + 1;
    ManifoldChain chain;
    chain.reserve(n);
    for (size_t j = 0; j < n; ++j) {
        const size_t i = from + size_t(step * int(j));
        const auto v = chartOf(V[i], V[j == 0 ? from + size_t(step) : i - size_t(step)]);
        if (!v) return std::nullopt;
        chain.push_back(*v);
    }
    for (size_t j = 1; j + 1 < n; ++j) {
        const Bsdf* bsdf = V[from + size_t(step * int(j))].bsdf;
        const auto eta = bsdf ? bsdf->eta() : std::nullopt;
        if (!setScattering(chain[j], chain[j - 1], chain[j + 1], eta, isDelta(V[from + size_t(step * int(j))])))
            return std::nullopt;
    }
    return chain;
}

std::vector<ChainInPath> specularChains(std::span<const PathVertex> V) {
    std::vector<ChainInPath> out;
    for (size_t a = 0; a + 2 < V.size(); ++a) {
        if (isDelta(V[a]) || !isDelta(V[a + 1])) continue;
        size_t b = a + 1;
        while (b < V.size() && isDelta(V[b]))
            ++b;
        if (b == V.size()) break; // the path ends in a delta vertex: no non-specular endpoint
        ChainInPath c;
        c.first = a;
        c.last = b;
        if (auto chain = manifoldChain(V, a, b)) c.chain = std::move(*chain);
        out.push_back(std::move(c));
        a = b - 1;
    }
    return out;
}

std::vector<ChainInPath> specularChains(const Scene& scene, const file::PathRecord& path, const std::string& name) {
    return specularChains(verticesFromRecord(scene, path, name));
}

void checkChain(const Scene& scene, ChainInPath& c, WalkStatistics& stats, double relativeStep,
                const WalkSettings& settings) {
    if (c.chain.empty()) return;
    c.G = generalizedGeometryTerm(c.chain);
    c.moving = c.chain.back().onSurface() ? WalkEnd::Last : WalkEnd::First;
    const bool last = c.moving == WalkEnd::Last;
    const ManifoldVertex end = last ? c.chain.back() : c.chain.front();
    if (!end.onSurface()) return;
    c.walkable = true;
    // The stored vertices come from float intersections, on the manifold only to about 1e-7 relative,
    // amplified along the chain. Re-trace the chain from its pinned end (ending on the tangent plane of
    // the moving end) and walk it to the stored endpoint: the walk "from the path to itself", whose
    // result is the exact chain the other walks start from and must return to.
    const ManifoldChain oriented = last ? c.chain : reversed(c.chain);
    const auto traced = propagateChain(scene, oriented, oriented[1].p, planeVertex(end.p, end.ng),
                                       settings.relativeTolerance * scene.bounds.diagonal());
    if (traced.failure != WalkFailure::None) {
        c.exact = {traced.failure, 0, {}};
        return;
    }
    c.exact = walkManifold(scene, traced.chain, end, WalkEnd::Last, settings);
    if (!c.exact.converged()) return;
    c.chain = last ? c.exact.chain : reversed(c.exact.chain);
    const ManifoldVertex& inner = last ? c.chain[c.chain.size() - 2] : c.chain[1];
    // A nearby point of the same surface: along the chart's diagonal, found by a ray from the chain's
    // neighbouring vertex so that it is a real surface point.
    const Vec3 aim = end.p + (end.dpdu + end.dpdv) * (relativeStep * scene.bounds.diagonal() / std::sqrt(2.0));
    const auto si = scene.intersect(spawnRay(inner.endpoint(), normalize(aim - inner.p)));
    if (!si || si->shape != end.shape) return;
    const auto target = manifoldVertex(*si);
    if (!target) return;
    c.perturbed = walkManifold(scene, c.chain, *target, c.moving, settings);
    if (c.perturbed->converged()) {
        c.reverse = reverseWalk(scene, c.chain, c.perturbed->chain, c.moving, settings);
        // A walk that does not come back is a failed proposal in MCMC (ME section 5.1 step 4).
        stats.add(c.reverse->converged() ? *c.perturbed : *c.reverse, c.chain.size());
    } else {
        stats.add(*c.perturbed, c.chain.size());
    }
}

void printManifoldReport(std::ostream& out, const Scene& scene, std::span<const file::PathRecord> paths,
                         size_t listed) {
    WalkStatistics stats;
    size_t withChains = 0, chains = 0, rebuilt = 0, walkable = 0, exactConverged = 0;
    const auto outcome = [](const WalkResult& w) {
        return w.converged() ? "converged in " + std::to_string(w.iterations)
                             : "failed (" + std::string(walkFailureName(w.failure)) + ")";
    };
    size_t unfit = 0;
    std::string firstUnfit;
    for (size_t i = 0; i < paths.size(); ++i) {
        std::vector<ChainInPath> found;
        try {
            found = specularChains(scene, paths[i], "path " + std::to_string(i));
        } catch (const Error& e) {
            if (unfit++ == 0) firstUnfit = e.what();
            continue;
        }
        if (found.empty()) continue;
        ++withChains;
        const bool show = withChains <= listed;
        if (show) out << "path " << i << " (s=" << paths[i].s << ", t=" << paths[i].t << ")\n";
        for (ChainInPath& c : found) {
            ++chains;
            checkChain(scene, c, stats);
            rebuilt += !c.chain.empty();
            walkable += c.walkable;
            exactConverged += c.walkable && c.exact.converged();
            if (!show) continue;
            out << "  chain vertices " << c.first << ".." << c.last << ": ";
            if (c.chain.empty()) {
                out << "could not be rebuilt on this scene\n";
                continue;
            }
            out << "G = " << (c.G ? std::to_string(*c.G) : std::string("singular"));
            if (!c.walkable) {
                out << ", no end with a surface to walk (a pinhole or a light at infinity at both ends)\n";
                continue;
            }
            out << ", walk of the " << (c.moving == WalkEnd::Last ? "eye" : "light")
                << " end to itself: " << outcome(c.exact);
            if (c.perturbed) {
                out << "; to a nearby point: " << outcome(*c.perturbed);
                if (c.reverse) out << ", back: " << outcome(*c.reverse);
            }
            out << "\n";
        }
    }
    if (withChains > listed) out << "(" << withChains - listed << " more paths with chains not listed)\n";
    if (unfit > 0) out << unfit << " paths do not fit this scene and were skipped (the first: " << firstUnfit << ")\n";
    out << "paths " << paths.size() << ", with specular chains " << withChains << ", chains " << chains << " (rebuilt "
        << rebuilt << ", with an end to walk " << walkable << "), walks to themselves converged " << exactConverged
        << "/" << walkable << "\n";
    out << "walks to a nearby point (relative step 1e-3 of the scene diagonal, reverse walk included):\n";
    stats.print(out);
}

} // namespace lt
