// Tangents for normal maps where the file gives none: glTF asks for
// MikkTSpace's (geometry/mikktspace.h), from the positions, normals and the
// normal texture's texture coordinates.
#pragma once

#include <string>

#include "geometry/scene.h"

namespace rt {

// For every triangle whose material has a normal texture and a vertex
// without a tangent (Scene::tangents empty, or w == 0): MikkTSpace tangents
// of all such triangles together, in glTF's sign convention. MikkTSpace gives
// one per corner, so a vertex whose corners disagree is split: the corner
// takes a copy of the vertex, every attribute duplicated, with its tangent.
// Vertices with a tangent of their own keep it. Run it once the normals are
// complete (finalise, loader.cpp); it adds a warning where the texture
// coordinates the map reads are missing.
void generate_tangents(Scene& scene, const std::string& name);

}  // namespace rt
