// What lt-seed and lt-gradient do between reading their options and writing their files: render a scene with one
// pixel estimator of the registry (run/estimator_registry.h) through the render loop (sampling/render.h), and
// hand back the image with the tables and the line that report the run.
#pragma once

#include <string>
#include <vector>

#include "formats/ltfile.h"
#include "sampling/render.h"
#include "sampling/seed_reservoir.h"

namespace lt {

struct RenderOutcome {
    RenderStats stats;
    file::Buffer image;
    std::vector<file::StatTable> tables; // "run" (formats/SPEC.md), then the estimator's own
    // "4 spp in 1.2 s (123k samples/s, 4.5M rays/s)", the estimator's summary and the samples dropped as
    // non-finite, for the user.
    std::string summary;
};

// Renders `estimator` over the scene's film; with `seeds`, every joined path is offered to it as a candidate seed
// path (sampling/render.h).
[[nodiscard]] RenderOutcome renderImage(const Scene& scene, const PixelEstimator& estimator,
                                        const RenderSettings& settings, const RunControl& control,
                                        SeedReservoir* seeds = nullptr);

} // namespace lt
