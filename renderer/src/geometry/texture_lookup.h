// A material's texture read at a surface hit: the texture coordinate set the
// reference names, through its KHR_texture_transform, filtered over the hit's
// ray cone footprint (Akenine-Möller et al., Ray Tracing Gems 2019, ch. 20).
#pragma once

#include "geometry/scene.h"
#include "geometry/surface.h"
#include "geometry/texture.h"

namespace rt {

// Linear RGBA of the texture `ref` names at the hit, filtered over the hit's
// ray cone footprint (SurfaceHit::cone_width; none gives the bilinear level 0);
// white for a reference to no texture.
glm::vec4 lookup(const Scene& scene, const TextureRef& ref, const SurfaceHit& s);

// The mip level lookup() reads `texture` at: the ray cone's footprint at the
// hit in texels of level 0, as a log2 (integrator/ray_cone.h). -inf without a
// cone or without texture coordinates.
float texture_lod(const Texture& texture, const TextureRef& ref, const SurfaceHit& s);

}  // namespace rt
