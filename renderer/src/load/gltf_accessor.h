// Reading glTF accessors from untrusted files: every element an accessor claims
// is checked to lie inside its buffer view and buffer before any is read, and
// elements are copied out byte-wise (no unaligned or aliased loads).
//
// A sparse accessor, and one without a buffer view (all zeros), is
// materialised into storage of its own with the dense element layout, then read
// like any other.
#pragma once

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "util/math.h"
#include "load/third_party.h"

namespace rt {

// What a materialised accessor may take. No file data backs its elements, so a
// count of a few digits could otherwise ask for gigabytes; 256 MiB hold 2^24
// VEC4 floats, an attribute of sixteen million vertices.
inline constexpr size_t kMaxMaterialisedAccessorBytes = size_t(256) << 20;

// tinygltf 2.7 refuses a primitive's `indices` accessor without a bufferView,
// which glTF allows (zeros, then its sparse values). Before parsing, each such
// accessor gets bufferView 0 and this extension of ours, which GltfAccessor
// takes to mean that it has none. (A file that names it itself gains nothing
// it could not have by leaving out the bufferView.)
inline constexpr const char* kNoBufferViewMark = "RT_no_buffer_view";
// Marks those accessors in the document; returns whether it changed. Files
// without any bufferView keep theirs unmarked, for tinygltf to refuse.
bool mark_viewless_indices(nlohmann::json& doc);

class GltfAccessor {
  public:
    // Throws SceneError naming `what` (e.g. "scene.gltf: meshes[0].primitives[1]
    // POSITION") when accessor `index` does not exist, is not of one of `types`
    // (TINYGLTF_TYPE_*) with one of `component_types`, has integer components
    // that are not normalized when `normalized_integers` asks for them, when
    // its elements (or its sparse indices and values) reach past the end of
    // their buffer view or buffer, or when its sparse indices are out of order
    // or out of range.
    GltfAccessor(const tinygltf::Model& model, int index, std::string what, std::initializer_list<int> types,
                 std::initializer_list<int> component_types, bool normalized_integers = false);
    GltfAccessor(const tinygltf::Model& model, int index, std::string what, int type,
                 std::initializer_list<int> component_types, bool normalized_integers = false)
        : GltfAccessor(model, index, std::move(what), {type}, component_types, normalized_integers) {}

    size_t count() const { return count_; }
    int type() const { return type_; }
    int component_type() const { return component_type_; }
    bool normalized() const { return normalized_; }
    const std::string& what() const { return what_; }

    // Element i < count() with each component decoded as glTF specifies:
    // FLOAT as it is, a normalized integer scaled to [0, 1] or [-1, 1]
    // (KHR_mesh_quantization's signed rule: max(c / 127, -1)), any other
    // integer converted to float. Components the accessor's type lacks are 0,
    // except vec4_at's w, which is 1 (a VEC3 colour is opaque).
    float float_at(size_t i) const { return component(element(i), 0); }
    vec2 vec2_at(size_t i) const;
    vec3 vec3_at(size_t i) const;
    glm::vec4 vec4_at(size_t i) const;
    // Element i of a SCALAR UNSIGNED_BYTE/SHORT/INT accessor.
    uint32_t index_at(size_t i) const;

  private:
    // The buffer view `view_index` and the `count` elements of `element_size`
    // bytes from `byte_offset` in it, checked; returns the first one and sets
    // `stride` (the view's byteStride when `strided` and it has one). `part`
    // names what reads it in messages ("" for the accessor itself).
    const unsigned char* locate(const tinygltf::Model& model, int view_index, size_t byte_offset, size_t count,
                                size_t element_size, bool strided, const std::string& part, size_t& stride) const;
    // Dense storage for a sparse accessor or one without a view.
    void materialise(const tinygltf::Model& model, const tinygltf::Accessor& accessor, int view_index);
    void apply_sparse(const tinygltf::Model& model, const tinygltf::Accessor& accessor);
    [[noreturn]] void fail(const std::string& problem) const;

    const unsigned char* element(size_t i) const {
        return (owned_.empty() ? data_ : owned_.data()) + i * stride_;
    }
    float component(const unsigned char* element, size_t k) const;

    std::string what_;
    const unsigned char* data_ = nullptr;  // into the model's buffer, unless owned_ holds the elements
    std::vector<unsigned char> owned_;
    size_t count_ = 0;
    size_t stride_ = 0;
    size_t element_size_ = 0;
    size_t components_ = 0;
    int type_ = 0;
    int component_type_ = 0;
    bool normalized_ = false;
};

}  // namespace rt
