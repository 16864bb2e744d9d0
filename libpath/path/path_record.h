// Converting a joined BDPT path into the stored path record (formats/records.h) and back to the
// scene's objects: the one place that knows how a PathVertex maps to a VertexRecord.
#pragma once

#include <string>
#include <vector>

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
// The vertices of a stored path re-created in `scene`, light to eye: the light vertex on its emitter, surface
// vertices from shape, primitive and barycentrics (BSDF and emitter attached), the camera vertex at the
// camera. Delta marks follow the record's technique: a BDPT technique's two connection ends were joined
// through their non-delta lobes whatever lobe their walk went on with; a chain state (s = t = 0) is marked
// exactly. Throws lt::Error "NAME: what" for a record that does not fit the scene.
[[nodiscard]] std::vector<PathVertex> verticesFromRecord(const Scene& scene, const file::PathRecord& record,
                                                         const std::string& name);
// The vertices of a strategy's path, light to eye, as a chain state holds them: the connection's two ends
// marked non-delta (they were joined through their non-delta lobes, whatever lobe their walks went on with).
[[nodiscard]] std::vector<PathVertex> joinedVertices(const StrategyPath& path);
// One vertex as stored.
[[nodiscard]] file::VertexRecord toVertexRecord(const Scene& scene, const PathVertex& v);

} // namespace lt
