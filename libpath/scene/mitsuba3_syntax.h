// Mitsuba 2 and 3 scenes read as Mitsuba 0.6 scenes: the one place that knows how the two syntaxes differ,
// so the scene builder speaks one vocabulary (0.6's). Mitsuba 3 upgrades a 0.6 file by renaming every
// property from camelCase to snake_case (mitsuba3 src/core/parser.cpp, upgrade_from_v1); lt reads a 3.x
// file by the inverse rename, plus the plugin differences that change an image (below, and
// translateMitsuba3Plugin). A name lt cannot translate keeps its written form and is reported as unread.
#pragma once

#include <string>

#include "scene/scene_object.h"

namespace lt {

// The vocabulary of a file, from its root's version attribute: "0.4.x" to "0.6.x" (and a file without a
// version) are Mitsuba 0.6; "2.x.y" and "3.x.y" are Mitsuba 3. Anything else throws lt::Error saying which
// versions lt reads (the caller puts the file and line in front).
[[nodiscard]] SceneSyntax sceneSyntaxOfVersion(const std::string& version);

// A Mitsuba 3 property name (or a nested object's name, such as a texture's "diffuse_reflectance") in
// Mitsuba 0.6's vocabulary: snake_case to camelCase (to_world -> toWorld, alpha_u -> alphaU), except where
// 0.6 spells it otherwise (int_ior -> intIOR, sample_border -> highQualityEdges).
[[nodiscard]] std::string mitsuba3PropertyName(const std::string& name);

// The Mitsuba 3 spelling of a 0.6 property name (toWorld -> to_world, intIOR -> int_ior): Mitsuba 3's own
// upgrade rule, for the error that meets a 0.6 name in a 3.x file. Mitsuba 3 names have no capitals.
[[nodiscard]] std::string mitsuba3Spelling(const std::string& name06);

// A property tag of a 3.x file in 0.6's: `int` -> `integer` (not Mitsuba 3's own spelling, which is
// `integer`, but written by scene exporters); the others are spelled alike.
[[nodiscard]] std::string mitsuba3PropertyTag(const std::string& tag);

// The plugin differences between Mitsuba 3 and 0.6 that change what a scene means, applied to an object
// of a 3.x file once its properties are translated:
//  - conductor, roughconductor: without material, eta or k, Mitsuba 3 is a perfect mirror (material
//    "none"); 0.6 defaults to copper. Given one of eta and k, Mitsuba 3 takes the other from the mirror
//    (eta 0, k 1); 0.6 wants both.
//  - textures (bitmap, checkerboard): `to_uv` (a 2-D scale and translation, uv' = M uv, as Mitsuba 3.6
//    and later apply it) becomes 0.6's uscale, vscale, uoffset, voffset (uv' = uv * scale + offset); a
//    rotation or shear has no 0.6 form and is refused.
//  - bitmap: `raw` = true reads the image as stored (0.6: gamma 1).
// Texture coordinates of PLY meshes (flip_tex_coords, Mitsuba 3.4 and later) are the builder's: it reads
// the object's syntax.
void translateMitsuba3Plugin(SceneObject& o);

} // namespace lt
