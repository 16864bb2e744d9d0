// The shading frame of a bump-mapped surface point (Mitsuba 0.6 bumpmap.cpp getFrame; Blinn 1978, "Simulation
// of Wrinkled Surfaces"): the surface displaced along its shading normal n by the displacement d(u, v) has
// tangents dp/du + n (dd/du - n . dp/du) and dp/dv + n (dd/dv - n . dp/dv) (the normal's own derivative
// terms dropped, as Mitsuba drops them), and their cross product is the bumped normal, turned to the
// geometric normal's side. d is the luminance of the texture; its gradient is the texture's (Texture::
// luminanceGradient).
//
// The normal's derivatives (dndu, dndv) stay those of the smooth surface, and the point is marked `bumped`:
// the manifold walks' transition densities need the bumped normal's true derivatives (the displacement's
// second derivatives), so no walk takes a bump-mapped vertex (manifold/manifold_vertex.h).
#pragma once

#include "scene/interaction.h"
#include "texture/texture.h"

namespace lt {

void applyBumpMap(SurfaceInteraction& si, const Texture& displacement);

} // namespace lt
