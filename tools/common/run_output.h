// What a render tool does with a run's progress and snapshots (sampling/run_clock.h): one progress line
// for every tool, and snapshots written as SNAP chunks of its output file.
#pragma once

#include <iomanip>
#include <sstream>
#include <string>

#include "common/progress.h"
#include "formats/ltfile.h"
#include "sampling/run_clock.h"

namespace lt::tool {

// Progress of a run on stderr: "2.5 spp, 3.10 s, 9.3 s left" with `unit` "spp" and `pixels` the film's
// pixel count (samples / pixels), or the phase and its time while a run does other work ("start-up, 3.10 s",
// "seeding with BDPT, 0.5 s").
inline RunProgressCallback runProgress(Progress& progress, double pixels, std::string unit) {
    return [&progress, pixels, unit = std::move(unit)](const RunProgress& p) {
        std::ostringstream d;
        const std::string phase = p.phase;
        if (phase != "render" && phase != "chains" && phase != "gradients") {
            d << phase << ", " << formatSeconds(p.wallSeconds);
        } else {
            d << std::setprecision(3) << double(p.samples) / pixels << ' ' << unit << ", "
              << formatSeconds(p.wallSeconds);
            if (p.fraction > 0.02 && p.fraction < 1)
                d << ", " << formatSeconds(p.wallSeconds * (1 / p.fraction - 1)) << " left";
        }
        progress.update(p.fraction, d.str());
    };
}

// Snapshots of a run as SNAP chunks of `writer`'s file, with the run's times and sample count.
inline RunSnapshotCallback snapshotWriter(file::Writer& writer) {
    return [&writer](const RunProgress& p, const file::Buffer& image) {
        file::Snapshot snap;
        snap.wallSeconds = p.wallSeconds;
        snap.cpuSeconds = p.cpuSeconds;
        snap.samples = p.samples;
        snap.overheadSeconds = p.snapshotSeconds;
        snap.buffer = image;
        writer.writeSnapshot(snap);
    };
}

} // namespace lt::tool
