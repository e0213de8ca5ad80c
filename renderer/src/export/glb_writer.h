// The glTF document and binary buffer an export builds, and the GLB file they
// become. It knows glTF's bookkeeping (buffer views, accessors, the one scene's
// nodes, the container) and nothing of what a Scene holds, so that
// glb_export.cpp and glb_materials.cpp read as the mapping alone.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "util/math.h"

namespace rt {

// glTF's enumerations (glTF 2.0 specification, section 5) that the mapping
// itself names; the writer keeps those of its buffer views and accessors.
inline constexpr int kGltfTriangles = 4;
inline constexpr int kGltfLinear = 9729;
inline constexpr int kGltfLinearMipmapLinear = 9987;

// A vector as a JSON array [x, y, z], the form of glTF's and rt.SceneExtras's vectors.
nlohmann::json gltf_array3(vec3 v);

class GlbWriter {
  public:
    using Json = nlohmann::json;

    GlbWriter();

    // Appends `item` to the document's top-level array `array` (created on first
    // use) and returns its index, by which the rest of the document refers to it.
    int append(const char* array, Json item);

    // The document itself, for what has no index: extensions, extensionsUsed.
    Json& doc() { return doc_; }

    // `bytes` of `data` as a buffer view (aligned to 4 bytes, as accessors need);
    // `target` 0 leaves the view without one, as images' views must be.
    int add_view(const void* data, size_t bytes, int target);
    int add_accessor(int view, int component_type, size_t count, const char* type);

    // Vertex attributes as float accessors; positions with the min and max
    // glTF requires of POSITION.
    int add_positions(const std::vector<vec3>& positions);
    int add_vec2s(const std::vector<vec2>& values);
    int add_vec3s(const std::vector<vec3>& values);
    int add_vec4s(const std::vector<glm::vec4>& values);
    int add_indices(const std::vector<uint32_t>& indices);

    // A node that is a root of the file's one scene.
    int add_node(Json node);

    // The GLB's bytes, with `scene` (its name, extras) as the one scene, holding
    // every node added. Throws std::length_error past a GLB's 4 GiB.
    std::string container(Json scene);

  private:
    Json doc_;
    Json scene_nodes_ = Json::array();
    std::string bin_;
};

}  // namespace rt
