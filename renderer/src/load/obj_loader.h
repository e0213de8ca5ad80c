// Wavefront OBJ in two steps: obj_loader.cpp checks the text and parses it with
// tinyobjloader; obj_scene.cpp turns what the parser hands back into our scene.
#pragma once

#include <span>
#include <vector>

#include "load/format_loaders.h"
#include "load/third_party.h"

namespace rt {

// The scene of a parsed OBJ: every index, count and number checked, materials
// converted (docs/materials.md) with their textures read through `folder`, and
// the objects and groups `motions` name moved. Throws SceneError prefixed with
// the scene's name, or with a motion's source, for anything invalid.
LoadedScene build_obj_scene(const SceneFolder& folder, const tinyobj::attrib_t& attrib,
                            const std::vector<tinyobj::shape_t>& shapes,
                            const std::vector<tinyobj::material_t>& materials,
                            std::span<const SceneAdditions::Motion> motions);

}  // namespace rt
