#include "load/gltf_accessor.h"

#include <algorithm>
#include <cstring>

#include "load/loader.h"

namespace rt {
namespace {

size_t component_size(int component_type) {
    switch (component_type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
        case TINYGLTF_COMPONENT_TYPE_INT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
        case TINYGLTF_COMPONENT_TYPE_DOUBLE: return 8;
        default: return 0;
    }
}

std::string component_name(int component_type) {
    switch (component_type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE: return "BYTE";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return "UNSIGNED_BYTE";
        case TINYGLTF_COMPONENT_TYPE_SHORT: return "SHORT";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return "UNSIGNED_SHORT";
        case TINYGLTF_COMPONENT_TYPE_INT: return "INT";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return "UNSIGNED_INT";
        case TINYGLTF_COMPONENT_TYPE_FLOAT: return "FLOAT";
        case TINYGLTF_COMPONENT_TYPE_DOUBLE: return "DOUBLE";
        default: return std::to_string(component_type);
    }
}

size_t component_count(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR: return 1;
        case TINYGLTF_TYPE_VEC2: return 2;
        case TINYGLTF_TYPE_VEC3: return 3;
        case TINYGLTF_TYPE_VEC4:
        case TINYGLTF_TYPE_MAT2: return 4;
        case TINYGLTF_TYPE_MAT3: return 9;
        case TINYGLTF_TYPE_MAT4: return 16;
        default: return 0;
    }
}

std::string type_name(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR: return "SCALAR";
        case TINYGLTF_TYPE_VEC2: return "VEC2";
        case TINYGLTF_TYPE_VEC3: return "VEC3";
        case TINYGLTF_TYPE_VEC4: return "VEC4";
        case TINYGLTF_TYPE_MAT2: return "MAT2";
        case TINYGLTF_TYPE_MAT3: return "MAT3";
        case TINYGLTF_TYPE_MAT4: return "MAT4";
        default: return std::to_string(type);
    }
}

template <typename T>
T load(const unsigned char* p) {
    T value;
    std::memcpy(&value, p, sizeof(T));
    return value;
}

}  // namespace

GltfAccessor::GltfAccessor(const tinygltf::Model& model, int index, std::string what, int type,
                           std::initializer_list<int> component_types)
    : what_(std::move(what)) {
    const auto fail = [&](const std::string& problem) { throw SceneError(what_ + " " + problem); };
    if (index < 0 || size_t(index) >= model.accessors.size())
        fail("refers to accessor " + std::to_string(index) + ", which does not exist");
    const tinygltf::Accessor& accessor = model.accessors[size_t(index)];
    what_ += " (accessors[" + std::to_string(index) + "])";

    if (accessor.sparse.isSparse) fail("is sparse, which is not supported");
    if (accessor.type != type)
        fail("has type " + type_name(accessor.type) + ", expected " + type_name(type));
    if (std::find(component_types.begin(), component_types.end(), accessor.componentType) ==
        component_types.end()) {
        std::string expected;
        for (int c : component_types) expected += (expected.empty() ? "" : " or ") + component_name(c);
        fail("has unsupported component type " + component_name(accessor.componentType) +
             ", expected " + expected);
    }
    component_type_ = accessor.componentType;
    normalized_ = accessor.normalized;

    const int view_index = accessor.bufferView;
    if (view_index < 0 || size_t(view_index) >= model.bufferViews.size())
        fail(view_index < 0 ? "has no bufferView (all-zero accessors are not supported)"
                            : "refers to bufferView " + std::to_string(view_index) +
                                  ", which does not exist");
    const tinygltf::BufferView& view = model.bufferViews[size_t(view_index)];
    const std::string view_name = "bufferViews[" + std::to_string(view_index) + "]";
    if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size())
        fail("uses " + view_name + ", which refers to buffer " + std::to_string(view.buffer) +
             ", which does not exist");
    const std::vector<unsigned char>& buffer = model.buffers[size_t(view.buffer)].data;
    if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset)
        fail("uses " + view_name + " (byteOffset " + std::to_string(view.byteOffset) +
             ", byteLength " + std::to_string(view.byteLength) + "), which reaches past the end of buffers[" +
             std::to_string(view.buffer) + "] (" + std::to_string(buffer.size()) + " bytes)");

    const size_t element_size = component_size(accessor.componentType) * component_count(type);
    stride_ = view.byteStride != 0 ? view.byteStride : element_size;
    if (stride_ < element_size)
        fail("has elements of " + std::to_string(element_size) + " bytes, more than the byteStride " +
             std::to_string(stride_) + " of " + view_name);

    count_ = accessor.count;
    if (count_ == 0) return;
    // The last element must end inside the view: offset + (count - 1) * stride +
    // size <= length, evaluated so that no term can overflow.
    const bool fits = accessor.byteOffset <= view.byteLength &&
                      element_size <= view.byteLength - accessor.byteOffset &&
                      count_ - 1 <= (view.byteLength - accessor.byteOffset - element_size) / stride_;
    if (!fits)
        fail("has " + std::to_string(count_) + " elements from byteOffset " +
             std::to_string(accessor.byteOffset) + ", which reach past the end of " + view_name + " (" +
             std::to_string(view.byteLength) + " bytes)");
    data_ = buffer.data() + view.byteOffset + accessor.byteOffset;
}

vec3 GltfAccessor::vec3_at(size_t i) const {
    const unsigned char* p = element(i);
    return vec3(load<float>(p), load<float>(p + 4), load<float>(p + 8));
}

vec2 GltfAccessor::vec2_at(size_t i) const {
    const unsigned char* p = element(i);
    switch (component_type_) {
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return vec2(float(p[0]), float(p[1])) / 255.0f;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
            return vec2(float(load<uint16_t>(p)), float(load<uint16_t>(p + 2))) / 65535.0f;
        default:
            return vec2(load<float>(p), load<float>(p + 4));
    }
}

uint32_t GltfAccessor::index_at(size_t i) const {
    const unsigned char* p = element(i);
    switch (component_type_) {
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return p[0];
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return load<uint16_t>(p);
        default: return load<uint32_t>(p);
    }
}

float GltfAccessor::float_at(size_t i) const { return load<float>(element(i)); }

glm::vec4 GltfAccessor::vec4_at(size_t i) const {
    const unsigned char* p = element(i);
    return glm::vec4(load<float>(p), load<float>(p + 4), load<float>(p + 8), load<float>(p + 12));
}

}  // namespace rt
