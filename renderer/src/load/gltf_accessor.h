// Reading glTF accessors from untrusted files: every element an accessor claims
// is checked to lie inside its buffer view and buffer before any is read, and
// elements are copied out byte-wise (no unaligned or aliased loads).
#pragma once

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <string>

#include "util/math.h"
#include "load/third_party.h"

namespace rt {

class GltfAccessor {
  public:
    // Throws SceneError naming `what` (e.g. "scene.gltf: meshes[0].primitives[1]
    // POSITION") when accessor `index` does not exist, is sparse or has no buffer
    // view, is not of `type` (TINYGLTF_TYPE_*) with one of `component_types`, or
    // when its elements reach past the end of its buffer view or buffer.
    GltfAccessor(const tinygltf::Model& model, int index, std::string what, int type,
                 std::initializer_list<int> component_types);

    size_t count() const { return count_; }
    int component_type() const { return component_type_; }
    bool normalized() const { return normalized_; }
    const std::string& what() const { return what_; }

    // Element i < count() of a FLOAT VEC3 accessor.
    vec3 vec3_at(size_t i) const;
    // Element i of a VEC2 accessor: FLOAT, or normalized UNSIGNED_BYTE/SHORT.
    vec2 vec2_at(size_t i) const;
    // Element i of a SCALAR UNSIGNED_BYTE/SHORT/INT accessor.
    uint32_t index_at(size_t i) const;
    // Element i of a FLOAT SCALAR accessor.
    float float_at(size_t i) const;
    // Element i of a FLOAT VEC4 accessor.
    glm::vec4 vec4_at(size_t i) const;

  private:
    const unsigned char* element(size_t i) const { return data_ + i * stride_; }

    std::string what_;
    const unsigned char* data_ = nullptr;
    size_t count_ = 0;
    size_t stride_ = 0;
    int component_type_ = 0;
    bool normalized_ = false;
};

}  // namespace rt
