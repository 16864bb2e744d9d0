#include "sampling/direct_split.h"

#include <algorithm>

#include "formats/ltfile.h"
#include "sampling/path_tracer.h"

namespace lt {

RenderStats renderDirectPart(const Scene& scene, const PathSettings& paths, const DirectSplit& split, uint64_t seed,
                             SampleFilm& film, const RunControl& control) {
    RenderSettings settings;
    settings.paths = paths;
    settings.paths.maxDepth = DirectSplit::Edges;
    settings.spp = split.samples;
    settings.seed = mixBits(seed ^ 0xd1ec7ULL);
    settings.sampler = SamplerKind::Sobol; // stratified: the direct part's noise falls faster than 1 / N
    const PathTracer estimator(scene, settings.paths);
    RunControl part = control;
    part.snapshot = {}; // the chains' film is not a complete image before they ran
    // Its progress is a phase of the chains' run, whose fraction and units are the chains': said as the phase alone.
    if (control.progress)
        part.progress = [&control](const RunProgress& p) {
            RunProgress phase = p;
            phase.phase = "direct part";
            phase.fraction = -1;
            control.progress(phase);
        };
    return render(scene, estimator, settings, film, part);
}

namespace {

double meanLuminance(const std::vector<std::vector<float>>& rgb) {
    double sum = 0;
    for (size_t i = 0; i < rgb[0].size(); ++i)
        sum += Spectrum(rgb[0][i], rgb[1][i], rgb[2][i]).luminance();
    return rgb[0].empty() ? 0.0 : sum / double(rgb[0].size());
}

} // namespace

DirectSplitRecord directSplitRecord(const SampleFilm& film, const file::Buffer& image, const DirectSplit& split,
                                    const RenderStats& direct) {
    DirectSplitRecord r;
    r.planes = film.developPlanes(0); // the camera samples alone
    const double directMean = meanLuminance(r.planes);
    const double total = meanLuminance({image.planes[0], image.planes[1], image.planes[2]});
    r.share = total > 0 ? directMean / total : 0.0;
    const double pixels = double(film.width()) * double(film.height());
    r.table = file::valueTable("direct_split", {{"samples_per_pixel", double(split.samples)},
                                                {"spp_rendered", double(direct.samples) / pixels},
                                                {"max_edges", double(DirectSplit::Edges)},
                                                {"seconds", direct.wallSeconds},
                                                {"rays", double(direct.rays)},
                                                {"direct_mean", directMean},
                                                {"chains_mean", total - directMean},
                                                {"direct_share", r.share}});
    return r;
}

} // namespace lt
