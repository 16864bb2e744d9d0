// Converting a joined BDPT path into the stored path record (formats/records.h) and back to the
// scene's objects: the one place that knows how a PathVertex maps to a VertexRecord.
#pragma once

#include "formats/records.h"
#include "path/strategy_path.h"
#include "scene/scene.h"

namespace lt {

// A strategy path's resampling weight: the luminance of its MIS-weighted contribution (never negative).
[[nodiscard]] double strategyWeight(const StrategyPath& path);
// The record of a strategy's path, light-to-eye order (records.h), with its raster position, technique,
// unweighted contribution, MIS weight and resampling weight strategyWeight. `stream` and
// `offset` name the random numbers it came from (lt-seed: pixel index and pass) for replay.
[[nodiscard]] file::PathRecord toPathRecord(const Scene& scene, const StrategyPath& path, uint64_t stream,
                                            uint64_t offset);
// One vertex as stored.
[[nodiscard]] file::VertexRecord toVertexRecord(const Scene& scene, const PathVertex& v);

} // namespace lt
