// glTF accessors beyond plain floats in a buffer view: every component type
// KHR_mesh_quantization allows, decoded as the spec says; sparse accessors with
// and without a base view; accessors without a view (zeros); and the vertex
// attributes TEXCOORD_1, COLOR_0 and TANGENT as they land in the scene.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <type_traits>

#include <gtest/gtest.h>

#include "loader_test_util.h"
#include "load/gltf_accessor.h"

namespace rt {
namespace {

using namespace rt::testing;

constexpr int kByte = TINYGLTF_COMPONENT_TYPE_BYTE, kUbyte = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
              kShort = TINYGLTF_COMPONENT_TYPE_SHORT, kUshort = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
              kUint = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, kFloat = TINYGLTF_COMPONENT_TYPE_FLOAT;

#define EXPECT_MENTIONS(error, part) EXPECT_TRUE(contains(error, part)) << (error)

// A parsed model built directly: one buffer, views and accessors into it.
struct Model {
    tinygltf::Model model;
    Model() { model.buffers.emplace_back(); }

    int view(const Bytes& bytes, size_t stride = 0) {
        Bytes& buffer = model.buffers[0].data;
        while (buffer.size() % 4 != 0) buffer.push_back(0xEE);
        tinygltf::BufferView v;
        v.buffer = 0;
        v.byteOffset = buffer.size();
        v.byteLength = bytes.size();
        v.byteStride = stride;
        buffer.insert(buffer.end(), bytes.begin(), bytes.end());
        model.bufferViews.push_back(v);
        return int(model.bufferViews.size() - 1);
    }
    int accessor(int view, int component_type, int type, size_t count, bool normalized = false) {
        tinygltf::Accessor a;
        a.bufferView = view;
        a.componentType = component_type;
        a.type = type;
        a.count = count;
        a.normalized = normalized;
        model.accessors.push_back(a);
        return int(model.accessors.size() - 1);
    }
    // Sparse substitution on accessor `index`: `indices` of `index_type`, values as bytes.
    void sparse(int index, const Bytes& indices, int index_type, size_t count, const Bytes& values) {
        auto& s = model.accessors[size_t(index)].sparse;
        s.isSparse = true;
        s.count = int(count);
        s.indices.bufferView = view(indices);
        s.indices.byteOffset = 0;
        s.indices.componentType = index_type;
        s.values.bufferView = view(values);
        s.values.byteOffset = 0;
    }
    GltfAccessor read(int index, int type, std::initializer_list<int> components = {kFloat, kByte, kUbyte, kShort,
                                                                                       kUshort, kUint}) const {
        return GltfAccessor(model, index, "test", type, components);
    }
    std::string error(int index, int type) const {
        return scene_error([&] { read(index, type); });
    }
};

template <typename T>
Bytes bytes_of(const std::vector<T>& values) {
    Bytes out;
    append(out, values);
    return out;
}

// The spec's decoding of one component (glTF 2.0, "Animations" and
// KHR_mesh_quantization: signed values max(c / (2^(n-1) - 1), -1)).
float reference(int component_type, bool normalized, int64_t c) {
    if (!normalized) return float(c);
    switch (component_type) {
        case kByte: return std::max(float(c) / 127.0f, -1.0f);
        case kUbyte: return float(c) / 255.0f;
        case kShort: return std::max(float(c) / 32767.0f, -1.0f);
        default: return float(c) / 65535.0f;
    }
}

// Raw components spanning the type's range, its ends included.
template <typename T>
std::vector<T> extremes() {
    const int64_t lo = std::numeric_limits<T>::min(), hi = std::numeric_limits<T>::max();
    return {T(lo), T(hi), T(0), T(1), T(lo + 1), T(hi / 3), T(hi - 1), T(lo / 2)};
}

template <typename T>
void expect_decodes(int component_type) {
    const std::vector<T> raw = extremes<T>();
    for (const bool normalized : {false, true}) {
        // The same 8 components as two VEC4, four VEC2 and, strided by 4 components, two VEC3.
        Model m;
        const int view = m.view(bytes_of(raw));
        const int strided = m.view(bytes_of(raw), 4 * sizeof(T));
        const GltfAccessor v4 = m.read(m.accessor(view, component_type, TINYGLTF_TYPE_VEC4, 2, normalized),
                                       TINYGLTF_TYPE_VEC4);
        const GltfAccessor v2 = m.read(m.accessor(view, component_type, TINYGLTF_TYPE_VEC2, 4, normalized),
                                       TINYGLTF_TYPE_VEC2);
        const GltfAccessor v3 = m.read(m.accessor(strided, component_type, TINYGLTF_TYPE_VEC3, 2, normalized),
                                       TINYGLTF_TYPE_VEC3);
        for (size_t k = 0; k < raw.size(); ++k) {
            const float expected = reference(component_type, normalized, int64_t(raw[k]));
            const std::string label = std::to_string(component_type) + (normalized ? " normalized" : "") +
                                      " component " + std::to_string(k);
            EXPECT_EQ(v4.vec4_at(k / 4)[int(k % 4)], expected) << label;
            EXPECT_EQ(v2.vec2_at(k / 2)[int(k % 2)], expected) << label;
            if (k % 4 < 3) {
                EXPECT_EQ(v3.vec3_at(k / 4)[int(k % 4)], expected) << label;
            }
        }
        // The ends of the range: signed minima clamp to -1, maxima reach 1.
        if (normalized) {
            EXPECT_EQ(v4.vec4_at(0)[1], 1.0f);
            EXPECT_EQ(v4.vec4_at(0)[0], std::is_signed_v<T> ? -1.0f : 0.0f);
        }
    }
}

TEST(LoaderAccessor, EveryQuantizedComponentTypeDecodesAsTheSpecSays) {
    expect_decodes<int8_t>(kByte);
    expect_decodes<uint8_t>(kUbyte);
    expect_decodes<int16_t>(kShort);
    expect_decodes<uint16_t>(kUshort);
    Model m;
    const std::vector<float> floats{0.5f, -2.0f, 1e30f};
    const GltfAccessor f = m.read(m.accessor(m.view(bytes_of(floats)), kFloat, TINYGLTF_TYPE_VEC3, 1),
                                  TINYGLTF_TYPE_VEC3);
    EXPECT_EQ(f.vec3_at(0), vec3(0.5f, -2.0f, 1e30f));
}

TEST(LoaderAccessor, Vec3ReadAsVec4IsOpaque) {
    Model m;
    const int a = m.accessor(m.view(bytes_of(std::vector<uint8_t>{255, 0, 51, 0})), kUbyte, TINYGLTF_TYPE_VEC3, 1,
                             true);
    const GltfAccessor colour(m.model, a, "COLOR_0", {TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4}, {kUbyte}, true);
    EXPECT_EQ(colour.vec4_at(0), glm::vec4(1.0f, 0.0f, 0.2f, 1.0f));
}

TEST(LoaderAccessor, IntegersThatMustBeNormalizedAreRefused) {
    Model m;
    const int a = m.accessor(m.view(bytes_of(std::vector<int8_t>{0, 0, 127, 0})), kByte, TINYGLTF_TYPE_VEC3, 1);
    const std::string error =
        scene_error([&] { GltfAccessor(m.model, a, "NORMAL", TINYGLTF_TYPE_VEC3, {kByte}, true); });
    EXPECT_MENTIONS(error, "NORMAL (accessors[0]) has BYTE components that are not normalized");
    m.model.accessors[0].normalized = true;
    EXPECT_EQ(GltfAccessor(m.model, a, "NORMAL", TINYGLTF_TYPE_VEC3, {kByte}, true).vec3_at(0), vec3(0, 0, 1));
}

TEST(LoaderAccessor, SparseOverABaseViewReplacesTheNamedElements) {
    Model m;
    const int a = m.accessor(m.view(bytes_of(std::vector<float>{1, 2, 3, 4, 5})), kFloat, TINYGLTF_TYPE_SCALAR, 5);
    m.sparse(a, bytes_of(std::vector<uint16_t>{1, 4}), kUshort, 2, bytes_of(std::vector<float>{-20, -50}));
    const GltfAccessor s = m.read(a, TINYGLTF_TYPE_SCALAR);
    ASSERT_EQ(s.count(), 5u);
    const float expected[] = {1, -20, 3, 4, -50};
    for (size_t i = 0; i < 5; ++i) EXPECT_EQ(s.float_at(i), expected[i]) << i;
}

TEST(LoaderAccessor, StridedBaseViewIsMaterialisedDensely) {
    Model m;
    // Two SHORT VEC3 in 8-byte strides, as quantized positions are laid out.
    const int a = m.accessor(m.view(bytes_of(std::vector<int16_t>{1, 2, 3, 99, 4, 5, 6, 99}), 8), kShort,
                             TINYGLTF_TYPE_VEC3, 2);
    m.sparse(a, bytes_of(std::vector<uint8_t>{0}), kUbyte, 1, bytes_of(std::vector<int16_t>{-7, -8, -9}));
    const GltfAccessor s = m.read(a, TINYGLTF_TYPE_VEC3);
    EXPECT_EQ(s.vec3_at(0), vec3(-7, -8, -9));
    EXPECT_EQ(s.vec3_at(1), vec3(4, 5, 6));
}

TEST(LoaderAccessor, NoViewReadsZerosThenSparseValues) {
    Model m;
    const int zeros = m.accessor(-1, kFloat, TINYGLTF_TYPE_VEC2, 3);
    const GltfAccessor z = m.read(zeros, TINYGLTF_TYPE_VEC2);
    for (size_t i = 0; i < 3; ++i) EXPECT_EQ(z.vec2_at(i), vec2(0.0f)) << i;
    const int a = m.accessor(-1, kUint, TINYGLTF_TYPE_SCALAR, 4);
    m.sparse(a, bytes_of(std::vector<uint32_t>{0, 3}), kUint, 2, bytes_of(std::vector<uint32_t>{7, 9}));
    const GltfAccessor s = m.read(a, TINYGLTF_TYPE_SCALAR);
    EXPECT_EQ(s.index_at(0), 7u);
    EXPECT_EQ(s.index_at(1), 0u);
    EXPECT_EQ(s.index_at(2), 0u);
    EXPECT_EQ(s.index_at(3), 9u);
}

// A sparse accessor of 4 floats over no view, with two substitutions.
Model sparse_model(std::vector<uint32_t> indices, size_t count = 2) {
    Model m;
    const int a = m.accessor(-1, kFloat, TINYGLTF_TYPE_SCALAR, 4);
    m.sparse(a, bytes_of(indices), kUint, count, bytes_of(std::vector<float>{1, 2}));
    return m;
}

TEST(LoaderAccessor, HostileSparseAccessorsAreRefusedByName) {
    EXPECT_MENTIONS(sparse_model({0, 4}).error(0, TINYGLTF_TYPE_SCALAR),
                    "test (accessors[0]) has sparse.indices element 1 = 4, out of range: the accessor has 4 elements");
    EXPECT_MENTIONS(sparse_model({2, 2}).error(0, TINYGLTF_TYPE_SCALAR),
                    "sparse.indices element 1 = 2 after 2: sparse indices must be strictly increasing");
    EXPECT_MENTIONS(sparse_model({3, 1}).error(0, TINYGLTF_TYPE_SCALAR), "must be strictly increasing");
    EXPECT_MENTIONS(sparse_model({0, 1, 2, 3, 3}, 5).error(0, TINYGLTF_TYPE_SCALAR),
                    "has sparse.count 5, which is not between 1 and its count 4");
    EXPECT_MENTIONS(sparse_model({0, 1}, 0).error(0, TINYGLTF_TYPE_SCALAR), "has sparse.count 0");
    // Three substitutions, but the views hold two indices and two values.
    Model past = sparse_model({0, 1, 2}, 3);
    EXPECT_MENTIONS(past.error(0, TINYGLTF_TYPE_SCALAR),
                    "sparse.values has 3 elements from byteOffset 0, which reach past the end of bufferViews[1]");
    Model indices = sparse_model({0, 1});
    indices.model.accessors[0].sparse.indices.byteOffset = 8;
    EXPECT_MENTIONS(indices.error(0, TINYGLTF_TYPE_SCALAR), "sparse.indices has 2 elements from byteOffset 8");
    Model type = sparse_model({0, 1});
    type.model.accessors[0].sparse.indices.componentType = kShort;
    EXPECT_MENTIONS(type.error(0, TINYGLTF_TYPE_SCALAR), "has sparse.indices of unsupported component type SHORT");
    Model view = sparse_model({0, 1});
    view.model.accessors[0].sparse.values.bufferView = 7;
    EXPECT_MENTIONS(view.error(0, TINYGLTF_TYPE_SCALAR), "sparse.values refers to bufferView 7, which does not exist");
}

TEST(LoaderAccessor, HugeCountWithoutAViewIsRefusedBeforeAllocating) {
    for (const size_t count : {kMaxMaterialisedAccessorBytes / 12 + 1, size_t(1) << 40, SIZE_MAX}) {
        Model m;
        m.accessor(-1, kFloat, TINYGLTF_TYPE_VEC3, count);
        EXPECT_MENTIONS(m.error(0, TINYGLTF_TYPE_VEC3), "elements without a bufferView: held in memory they would "
                                                        "take more than the limit of 256 MiB");
    }
}

}  // namespace
}  // namespace rt
