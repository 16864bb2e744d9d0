#include "run/render_job.h"

#include <iomanip>
#include <sstream>

#include "run/run_summary.h"

namespace lt {

RenderOutcome renderImage(const Scene& scene, const PixelEstimator& estimator, const RenderSettings& settings,
                          const RunControl& control, SeedReservoir* seeds) {
    SampleFilm film(scene.camera, estimator.planes());
    RenderOutcome out;
    out.stats = render(scene, estimator, settings, film, control, seeds);
    const RenderStats& s = out.stats;
    const double pixels = double(film.width()) * double(film.height());
    out.image = film.toBuffer();
    out.tables.push_back(runTable(
        s, {{"samples", double(s.samples)}, {"spp", double(s.samples) / pixels}, {"passes", double(s.passes)}}));
    for (auto& t : estimator.statistics())
        out.tables.push_back(std::move(t));
    std::ostringstream line;
    line << (s.interrupted ? "interrupted after " : "") << double(s.samples) / pixels << " spp in "
         << formatSeconds(s.wallSeconds) << " (" << std::setprecision(3) << double(s.samples) / s.wallSeconds / 1e3
         << "k samples/s, " << double(s.rays) / s.wallSeconds / 1e6 << "M rays/s)";
    if (const std::string more = estimator.summary(); !more.empty()) line << "; " << more;
    line << nonFiniteNote(s.health, "samples");
    out.summary = line.str();
    return out;
}

} // namespace lt
