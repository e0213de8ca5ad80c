#include "load/gltf_attributes.h"

#include "load/loader.h"

namespace rt {

int attribute_accessor(const tinygltf::Primitive& primitive, const char* semantic) {
    const auto it = primitive.attributes.find(semantic);
    return it == primitive.attributes.end() ? -1 : it->second;
}

GltfPrimitiveAttributes read_primitive_attributes(const tinygltf::Model& model, const tinygltf::Primitive& primitive,
                                                  const std::string& prefix) {
    const auto attribute = [&](const char* semantic) { return attribute_accessor(primitive, semantic); };
    // The component types of the core spec and KHR_mesh_quantization.
    using Types = std::initializer_list<int>;
    const Types quantized{TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_BYTE,
                          TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_SHORT,
                          TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT};
    const Types directions{TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_BYTE, TINYGLTF_COMPONENT_TYPE_SHORT};
    const Types colors{TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                       TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT};
    GltfPrimitiveAttributes a{
        GltfAccessor(model, attribute("POSITION"), prefix + " POSITION", TINYGLTF_TYPE_VEC3, quantized), {}, {}, {}, {},
        {}, {}};
    const size_t n = a.positions.count();
    const auto read = [&](std::optional<GltfAccessor>& out, const char* semantic, std::initializer_list<int> types,
                          std::initializer_list<int> components, bool normalized) {
        if (attribute(semantic) == -1) return;
        out.emplace(model, attribute(semantic), prefix + " " + semantic, types, components, normalized);
        if (out->count() != n)
            throw SceneError(out->what() + " has " + std::to_string(out->count()) + " elements, but POSITION has " +
                             std::to_string(n));
    };
    read(a.normals, "NORMAL", {TINYGLTF_TYPE_VEC3}, directions, true);
    read(a.texcoords, "TEXCOORD_0", {TINYGLTF_TYPE_VEC2}, quantized, false);
    read(a.texcoords1, "TEXCOORD_1", {TINYGLTF_TYPE_VEC2}, quantized, false);
    read(a.colors, "COLOR_0", {TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4}, colors, true);
    read(a.tangents, "TANGENT", {TINYGLTF_TYPE_VEC4}, directions, true);
    if (primitive.indices != -1)
        a.indices.emplace(model, primitive.indices, prefix + " indices", TINYGLTF_TYPE_SCALAR,
                          Types{TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                                TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT});
    return a;
}

std::vector<uint32_t> corner_vertices(const GltfPrimitiveAttributes& attributes, const std::string& what) {
    const size_t n = attributes.positions.count();
    const size_t c = attributes.indices ? attributes.indices->count() : n;
    std::vector<uint32_t> corners(c);
    for (size_t i = 0; i < c; ++i) {
        corners[i] = attributes.indices ? attributes.indices->index_at(i) : uint32_t(i);
        if (corners[i] >= n)
            throw SceneError(what + " index " + std::to_string(corners[i]) + " (element " + std::to_string(i) +
                             ") is out of range: POSITION has " + std::to_string(n) + " elements");
    }
    return corners;
}

}  // namespace rt
