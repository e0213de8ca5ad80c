// A material's texture read at a surface hit: the texture coordinate set the
// reference names, through its KHR_texture_transform.
#pragma once

#include "geometry/scene.h"
#include "geometry/surface.h"
#include "geometry/texture.h"

namespace rt {

// Linear RGBA; white for a reference to no texture.
glm::vec4 lookup(const Scene& scene, const TextureRef& ref, const SurfaceHit& s);

}  // namespace rt
