// A glTF primitive's vertex attributes and corners, read through GltfAccessor:
// each semantic with the types and component types the core specification and
// KHR_mesh_quantization allow it (integer normals, tangents and colours must be
// normalized), every count checked against POSITION's.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "load/gltf_accessor.h"
#include "load/third_party.h"

namespace rt {

struct GltfPrimitiveAttributes {
    GltfAccessor positions;
    std::optional<GltfAccessor> normals, texcoords, texcoords1, colors, tangents, indices;
};

// The accessor index of `semantic` in the primitive, -1 when it has none.
int attribute_accessor(const tinygltf::Primitive& primitive, const char* semantic);

// The primitive's attributes (it must have POSITION); `prefix` (file: mesh and
// primitive) starts every message.
GltfPrimitiveAttributes read_primitive_attributes(const tinygltf::Model& model, const tinygltf::Primitive& primitive,
                                                  const std::string& prefix);

// The vertex of each corner, in the order of the indices (or the vertices);
// throws SceneError naming `what` for an index past POSITION's count.
std::vector<uint32_t> corner_vertices(const GltfPrimitiveAttributes& attributes, const std::string& what);

}  // namespace rt
