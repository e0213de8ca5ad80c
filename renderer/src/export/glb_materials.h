// A scene's materials and the textures they use, written into a GLB document
// (glb_export.h describes the result). Apart from the mesh and the spheres
// because it is the one part of the mapping with glTF extensions to declare
// and a texture cache to keep.
#pragma once

#include "export/glb_writer.h"
#include "geometry/scene.h"

namespace rt {

// Whether `ref` names a texture the scene has: one past the end is exported as
// no texture rather than as an index the file cannot resolve.
bool has_texture(const Scene& scene, const TextureRef& ref);

// The scene's materials, in its order, so that a primitive's material index is
// the scene's; each texture embedded once as a PNG, however many use it; the
// KHR_materials_* and KHR_texture_transform extensions used declared.
void add_materials(const Scene& scene, GlbWriter& writer);

}  // namespace rt
