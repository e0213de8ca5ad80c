#include "load/gltf_accessor.h"

#include <algorithm>
#include <cstring>
#include <limits>

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

std::string names(std::initializer_list<int> values, std::string (*name)(int)) {
    std::string out;
    for (int v : values) out += (out.empty() ? "" : " or ") + name(v);
    return out;
}

template <typename T>
T load(const unsigned char* p) {
    T value;
    std::memcpy(&value, p, sizeof(T));
    return value;
}

}  // namespace

bool mark_viewless_indices(nlohmann::json& doc) {
    const auto array = [&](const char* key) -> nlohmann::json* {
        const auto it = doc.find(key);
        return it != doc.end() && it->is_array() ? &*it : nullptr;
    };
    nlohmann::json* meshes = array("meshes");
    nlohmann::json* accessors = array("accessors");
    nlohmann::json* views = array("bufferViews");
    if (!meshes || !accessors || !views || views->empty()) return false;
    bool changed = false;
    for (const nlohmann::json& mesh : *meshes) {
        const auto primitives = mesh.is_object() ? mesh.find("primitives") : mesh.end();
        if (!mesh.is_object() || primitives == mesh.end() || !primitives->is_array()) continue;
        for (const nlohmann::json& primitive : *primitives) {
            const auto indices = primitive.is_object() ? primitive.find("indices") : primitive.end();
            if (!primitive.is_object() || indices == primitive.end() || !indices->is_number_unsigned() ||
                indices->get<uint64_t>() >= accessors->size())
                continue;
            nlohmann::json& accessor = (*accessors)[indices->get<size_t>()];
            if (!accessor.is_object() || accessor.contains("bufferView")) continue;
            accessor["bufferView"] = 0;
            nlohmann::json& extensions = accessor["extensions"];
            if (!extensions.is_object()) extensions = nlohmann::json::object();
            extensions[kNoBufferViewMark] = nlohmann::json::object();
            changed = true;
        }
    }
    return changed;
}

GltfAccessor::GltfAccessor(const tinygltf::Model& model, int index, std::string what, std::initializer_list<int> types,
                           std::initializer_list<int> component_types, bool normalized_integers)
    : what_(std::move(what)) {
    if (index < 0 || size_t(index) >= model.accessors.size())
        fail("refers to accessor " + std::to_string(index) + ", which does not exist");
    const tinygltf::Accessor& accessor = model.accessors[size_t(index)];
    what_ += " (accessors[" + std::to_string(index) + "])";

    if (std::find(types.begin(), types.end(), accessor.type) == types.end())
        fail("has type " + type_name(accessor.type) + ", expected " + names(types, type_name));
    if (std::find(component_types.begin(), component_types.end(), accessor.componentType) == component_types.end())
        fail("has unsupported component type " + component_name(accessor.componentType) + ", expected " +
             names(component_types, component_name));
    type_ = accessor.type;
    component_type_ = accessor.componentType;
    normalized_ = accessor.normalized && component_type_ != TINYGLTF_COMPONENT_TYPE_FLOAT;
    if (normalized_integers && component_type_ != TINYGLTF_COMPONENT_TYPE_FLOAT && !normalized_)
        fail("has " + component_name(component_type_) +
             " components that are not normalized: only normalized integers are allowed here");
    components_ = component_count(type_);
    element_size_ = component_size(component_type_) * components_;
    count_ = accessor.count;

    const int view = accessor.extensions.count(kNoBufferViewMark) != 0 ? -1 : accessor.bufferView;
    if (accessor.sparse.isSparse || view == -1) {
        materialise(model, accessor, view);
        return;
    }
    data_ = locate(model, accessor.bufferView, accessor.byteOffset, count_, element_size_, true, "", stride_);
}

void GltfAccessor::fail(const std::string& problem) const { throw SceneError(what_ + " " + problem); }

const unsigned char* GltfAccessor::locate(const tinygltf::Model& model, int view_index, size_t byte_offset,
                                          size_t count, size_t element_size, bool strided, const std::string& part,
                                          size_t& stride) const {
    const std::string subject = part.empty() ? "" : part + " ";
    if (view_index < 0 || size_t(view_index) >= model.bufferViews.size())
        fail(subject + "refers to bufferView " + std::to_string(view_index) + ", which does not exist");
    const tinygltf::BufferView& view = model.bufferViews[size_t(view_index)];
    const std::string view_name = "bufferViews[" + std::to_string(view_index) + "]";
    if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size())
        fail(subject + "uses " + view_name + ", which refers to buffer " + std::to_string(view.buffer) +
             ", which does not exist");
    const std::vector<unsigned char>& buffer = model.buffers[size_t(view.buffer)].data;
    if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset)
        fail(subject + "uses " + view_name + " (byteOffset " + std::to_string(view.byteOffset) + ", byteLength " +
             std::to_string(view.byteLength) + "), which reaches past the end of buffers[" +
             std::to_string(view.buffer) + "] (" + std::to_string(buffer.size()) + " bytes)");

    stride = strided && view.byteStride != 0 ? view.byteStride : element_size;
    if (stride < element_size)
        fail(subject + "has elements of " + std::to_string(element_size) + " bytes, more than the byteStride " +
             std::to_string(stride) + " of " + view_name);
    if (count == 0) return nullptr;
    // The last element must end inside the view: offset + (count - 1) * stride +
    // size <= length, evaluated so that no term can overflow.
    const bool fits = byte_offset <= view.byteLength && element_size <= view.byteLength - byte_offset &&
                      count - 1 <= (view.byteLength - byte_offset - element_size) / stride;
    if (!fits)
        fail(subject + "has " + std::to_string(count) + " elements from byteOffset " + std::to_string(byte_offset) +
             ", which reach past the end of " + view_name + " (" + std::to_string(view.byteLength) + " bytes)");
    return buffer.data() + view.byteOffset + byte_offset;
}

void GltfAccessor::materialise(const tinygltf::Model& model, const tinygltf::Accessor& accessor, int view_index) {
    if (count_ > kMaxMaterialisedAccessorBytes / element_size_)
        fail("has " + std::to_string(count_) + " elements " +
             (view_index == -1 ? "without a bufferView" : "and is sparse") +
             ": held in memory they would take more than the limit of " +
             std::to_string(kMaxMaterialisedAccessorBytes >> 20) + " MiB");
    owned_.assign(count_ * element_size_, 0);  // no bufferView: all zeros
    stride_ = element_size_;
    if (view_index != -1) {
        size_t stride = 0;
        const unsigned char* base = locate(model, view_index, accessor.byteOffset, count_, element_size_,
                                           true, "", stride);
        for (size_t i = 0; i < count_; ++i) std::memcpy(&owned_[i * element_size_], base + i * stride, element_size_);
    }
    if (accessor.sparse.isSparse) apply_sparse(model, accessor);
}

// The spec's sparse storage: `count` strictly increasing indices, each with a
// value that replaces the element there, both tightly packed.
void GltfAccessor::apply_sparse(const tinygltf::Model& model, const tinygltf::Accessor& accessor) {
    const auto& sparse = accessor.sparse;
    if (sparse.count < 1 || size_t(sparse.count) > count_)
        fail("has sparse.count " + std::to_string(sparse.count) + ", which is not between 1 and its count " +
             std::to_string(count_));
    const size_t n = size_t(sparse.count);
    const int index_type = sparse.indices.componentType;
    if (index_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && index_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        index_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
        fail("has sparse.indices of unsupported component type " + component_name(index_type) +
             ", expected UNSIGNED_BYTE or UNSIGNED_SHORT or UNSIGNED_INT");
    if (sparse.indices.byteOffset < 0 || sparse.values.byteOffset < 0)
        fail("has a negative sparse byteOffset");
    const size_t index_size = component_size(index_type);
    size_t ignored = 0;
    const unsigned char* indices = locate(model, sparse.indices.bufferView, size_t(sparse.indices.byteOffset), n,
                                          index_size, false, "sparse.indices", ignored);
    const unsigned char* values = locate(model, sparse.values.bufferView, size_t(sparse.values.byteOffset), n,
                                         element_size_, false, "sparse.values", ignored);
    uint64_t previous = 0;
    for (size_t k = 0; k < n; ++k) {
        const unsigned char* p = indices + k * index_size;
        const uint64_t index = index_size == 1 ? p[0] : index_size == 2 ? load<uint16_t>(p) : load<uint32_t>(p);
        if (index >= count_)
            fail("has sparse.indices element " + std::to_string(k) + " = " + std::to_string(index) +
                 ", out of range: the accessor has " + std::to_string(count_) + " elements");
        if (k > 0 && index <= previous)
            fail("has sparse.indices element " + std::to_string(k) + " = " + std::to_string(index) + " after " +
                 std::to_string(previous) + ": sparse indices must be strictly increasing");
        std::memcpy(&owned_[size_t(index) * element_size_], values + k * element_size_, element_size_);
        previous = index;
    }
}

float GltfAccessor::component(const unsigned char* p, size_t k) const {
    switch (component_type_) {
        case TINYGLTF_COMPONENT_TYPE_BYTE: {
            const float c = float(load<int8_t>(p + k));
            return normalized_ ? std::max(c / 127.0f, -1.0f) : c;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
            const float c = float(p[k]);
            return normalized_ ? c / 255.0f : c;
        }
        case TINYGLTF_COMPONENT_TYPE_SHORT: {
            const float c = float(load<int16_t>(p + 2 * k));
            return normalized_ ? std::max(c / 32767.0f, -1.0f) : c;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
            const float c = float(load<uint16_t>(p + 2 * k));
            return normalized_ ? c / 65535.0f : c;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return float(load<uint32_t>(p + 4 * k));
        default: return load<float>(p + 4 * k);
    }
}

vec2 GltfAccessor::vec2_at(size_t i) const {
    const unsigned char* p = element(i);
    return vec2(component(p, 0), components_ > 1 ? component(p, 1) : 0.0f);
}

vec3 GltfAccessor::vec3_at(size_t i) const {
    const unsigned char* p = element(i);
    vec3 v(0.0f);
    for (size_t k = 0; k < std::min<size_t>(components_, 3); ++k) v[int(k)] = component(p, k);
    return v;
}

glm::vec4 GltfAccessor::vec4_at(size_t i) const {
    const unsigned char* p = element(i);
    glm::vec4 v(0.0f, 0.0f, 0.0f, 1.0f);
    for (size_t k = 0; k < std::min<size_t>(components_, 4); ++k) v[int(k)] = component(p, k);
    return v;
}

uint32_t GltfAccessor::index_at(size_t i) const {
    const unsigned char* p = element(i);
    switch (component_type_) {
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return p[0];
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return load<uint16_t>(p);
        default: return load<uint32_t>(p);
    }
}

}  // namespace rt
