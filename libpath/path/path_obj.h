// Stored paths as Wavefront OBJ polylines, to look at them in any 3D viewer next to the scene's meshes.
#pragma once

#include <span>
#include <string>

#include "formats/records.h"

namespace lt {

// One object per path, named "path_INDEX_sS_tT" (INDEX its position in `paths`), holding its vertices
// and one `l` element through them in light-to-eye order. Written to a temporary name and renamed when
// complete; errors are lt::Error naming `objPath`. `source` goes into the header comment.
void writePathsObj(const std::string& objPath, std::span<const file::PathRecord> paths, const std::string& source);

} // namespace lt
