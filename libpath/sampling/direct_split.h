// The direct split of a Markov-chain image (Veach and Guibas 1997, Sec. 5, "direct lighting": rendered with
// standard techniques, not by the chains; Mitsuba's MLT, PSSMLT and ERPT do so by default, `directSamples`).
// Paths of one edge (emitters seen directly: area lights, environment maps, the sun) and of two edges (direct
// illumination) are rendered by a pixel estimator, the path tracer with next-event estimation and MIS (Veach 1997,
// Sec. 9.2), at a fixed number of Sobol samples a pixel; the chains sample the rest (PathSettings::minDepth = 3):
// their target, start-up, seed paths and normalization b leave these paths out, and the image is the sum.
//
// Why: a chain's image is (b / N) sum f / f*, whose scale is b. Where a lamp a few pixels wide seen directly
// holds most of b, a start-up or seed run that misses it (or hits it once) moves the scale of every other pixel
// with it, and chains that find it spend their mutations on a few pixels a stratified pixel estimator gets right in
// a second. Both parts estimate disjoint sets of paths of the same measurement, so their sum is unbiased where
// each is.
#pragma once

#include <string>
#include <vector>

#include "formats/records.h"
#include "image/film.h"
#include "sampling/parallel_run.h"
#include "sampling/path_settings.h"
#include "sampling/render.h"

namespace lt {

struct DirectSplit {
    // The longest path of the direct part: one edge (emitters seen directly) and two (direct illumination).
    static constexpr int Edges = 2;
    int samples = 16; // per pixel (Mitsuba's default); -1: no split, the chains render every path

    // Throws lt::Error for a sample count that is neither -1 nor positive.
    void check() const {
        if (samples == 0 || samples < -1)
            throw Error("--direct-samples must be -1 (the chains render every path) or at least 1");
    }
    // Whether the split is made with these path settings: asked for, and the bound leaves the chains paths longer
    // than the direct part's (a max depth of 1 or 2 leaves them nothing, and the chains render everything).
    [[nodiscard]] bool appliesTo(const PathSettings& paths) const {
        return samples >= 0 && (paths.maxDepth < 0 || paths.maxDepth > Edges);
    }
    // The chains' path settings: paths of the direct part left out when the split applies.
    [[nodiscard]] PathSettings chainPaths(PathSettings paths) const {
        if (appliesTo(paths)) paths.minDepth = Edges + 1;
        return paths;
    }
};

// Renders the direct part into the camera samples of `film` (the chains' splats stay apart from them, so the film
// reads as their sum: image/film.h). Seeded from `seed`, with Russian roulette and MIS from `paths`.
RenderStats renderDirectPart(const Scene& scene, const PathSettings& paths, const DirectSplit& split, uint64_t seed,
                             SampleFilm& film, const RunControl& control);

// What the split's record says: the direct part's planes ("direct.R/G/B", appended to the image buffer) and a STAT
// table "direct_split" (formats/SPEC.md) with the samples, the part's time and rays, the mean luminance of each part
// and the direct part's share of the image.
struct DirectSplitRecord {
    std::vector<std::vector<float>> planes; // R, G, B of the direct part
    file::StatTable table;
    double share = 0; // the direct part's share of the image's mean luminance
};
// `film` holds the direct part as its camera samples; `image` is the whole image as the film was read.
[[nodiscard]] DirectSplitRecord directSplitRecord(const SampleFilm& film, const file::Buffer& image,
                                                  const DirectSplit& split, const RenderStats& direct);

} // namespace lt
