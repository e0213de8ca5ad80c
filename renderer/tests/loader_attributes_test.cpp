// glTF vertex attributes as they land in the scene: KHR_mesh_quantization's
// integer positions, normals and texture coordinates under their dequantizing
// node, sparse and view-less accessors read by the loader, and TEXCOORD_1,
// COLOR_0 and TANGENT with their defaults for meshes without them.
#include <cmath>

#include <gtest/gtest.h>

#include "loader_test_util.h"

namespace rt {
namespace {

using namespace rt::testing;

#define EXPECT_MENTIONS(error, part) EXPECT_TRUE(contains(error, part)) << (error)

constexpr int kByte = 5120, kUbyte = 5121, kShort = 5122, kUshort = 5123, kUint = 5125, kFloat = 5126;

// A triangle of float positions with its origin at `x`.
Json triangle_at(GltfDoc& doc, float x) {
    return {{"POSITION", doc.add_vec3({x, 0, 0, x + 1, 0, 0, x, 1, 0})}};
}

void expect_near(glm::vec4 actual, glm::vec4 expected, const std::string& label) {
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(actual[k], expected[k], 1e-6f) << label << " component " << k;
}

TEST(LoaderAttributes, QuantizedMeshLoadsUnderItsDequantizingNode) {
    GltfDoc doc;
    // SHORT positions padded to 8 bytes, as KHR_mesh_quantization lays them out.
    const int positions = doc.add_accessor(std::vector<int16_t>{0, 0, 0, 0, 1000, 0, 0, 0, 0, 2000, 0, 0}, kShort,
                                           "VEC3", 4);
    doc.json["accessors"][size_t(positions)]["count"] = 3;
    doc.json["bufferViews"][size_t(positions)]["byteStride"] = 8;
    const int normals = doc.add_accessor(std::vector<int8_t>{0, 0, 127, 0, 0, 0, -128, 0, 0, 90, 90, 0}, kByte,
                                         "VEC3", 4);
    doc.json["accessors"][size_t(normals)]["count"] = 3;
    doc.json["accessors"][size_t(normals)]["normalized"] = true;
    doc.json["bufferViews"][size_t(normals)]["byteStride"] = 4;
    const int uv = doc.add_accessor(std::vector<uint16_t>{0, 65535, 32768, 0, 65535, 13107}, kUshort, "VEC2", 2);
    doc.json["accessors"][size_t(uv)]["normalized"] = true;
    doc.add_mesh_node({{"attributes", {{"POSITION", positions}, {"NORMAL", normals}, {"TEXCOORD_0", uv}}}},
                      {{"scale", {0.001, 0.001, 0.001}}, {"translation", {1, 0, 0}}});
    doc.json["extensionsUsed"] = {"KHR_mesh_quantization"};
    doc.json["extensionsRequired"] = {"KHR_mesh_quantization"};

    const Scene scene = load_text(doc.text(), "q.gltf");
    ASSERT_EQ(scene.positions.size(), 3u);
    const vec3 expected_positions[] = {{1, 0, 0}, {2, 0, 0}, {1, 2, 0}};
    const vec3 expected_normals[] = {{0, 0, 1}, {0, 0, -1}, glm::normalize(vec3(0, 1, 1))};
    const vec2 expected_uv[] = {{0, 1}, {32768 / 65535.0f, 0}, {1, 0.2f}};
    for (size_t i = 0; i < 3; ++i) {
        EXPECT_NEAR(glm::distance(scene.positions[i], expected_positions[i]), 0.0f, 1e-6f) << i;
        EXPECT_NEAR(glm::distance(scene.normals[i], expected_normals[i]), 0.0f, 1e-6f) << i;
        EXPECT_NEAR(glm::distance(scene.texcoords[i], expected_uv[i]), 0.0f, 1e-6f) << i;
    }
}

TEST(LoaderAttributes, IntegerNormalsThatAreNotNormalizedAreRefused) {
    GltfDoc doc;
    const Json attributes = triangle_at(doc, 0);
    const int normals = doc.add_accessor(std::vector<int16_t>{0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0}, kShort, "VEC3", 4);
    doc.json["accessors"][size_t(normals)]["count"] = 3;
    Json with_normals = attributes;
    with_normals["NORMAL"] = normals;
    doc.add_mesh_node({{"attributes", with_normals}});
    EXPECT_MENTIONS(scene_error([&] { load_text(doc.text(), "n.gltf"); }),
                    "n.gltf: meshes[0].primitives[0] NORMAL (accessors[1]) has SHORT components that are not "
                    "normalized");
}

TEST(LoaderAttributes, SparsePositionsAndIndicesAreRead) {
    GltfDoc doc;
    const Json attributes = triangle_at(doc, 0);
    // Vertex 2 moves to (0, 5, 0); the indices come from no view at all, all zeros but where sparse says
    // (which tinygltf 2.7 refuses by itself: see mark_viewless_indices).
    const int moved = doc.add_accessor(std::vector<uint8_t>{2, 0, 0, 0}, kUbyte, "SCALAR", 1);
    const int value = doc.add_vec3({0, 5, 0});
    doc.json["accessors"][0]["sparse"] = {{"count", 1},
                                          {"indices", {{"bufferView", moved}, {"componentType", kUbyte}}},
                                          {"values", {{"bufferView", value}}}};
    const int which = doc.add_accessor(std::vector<uint16_t>{1, 2}, kUshort, "SCALAR", 1);
    const int corners = doc.add_accessor(std::vector<uint32_t>{1, 2}, kUint, "SCALAR", 1);
    Json indices = {{"componentType", kUint}, {"count", 3}, {"type", "SCALAR"},
                    {"sparse", {{"count", 2}, {"indices", {{"bufferView", which}, {"componentType", kUshort}}},
                                {"values", {{"bufferView", corners}}}}}};
    doc.json["accessors"].push_back(indices);
    doc.add_mesh_node({{"attributes", attributes}, {"indices", doc.json["accessors"].size() - 1}});

    const Scene scene = load_text(doc.text(), "s.gltf");
    ASSERT_EQ(scene.triangles.size(), 1u);
    EXPECT_EQ(scene.triangles[0], uvec3(0, 1, 2));
    EXPECT_EQ(scene.positions[1], vec3(1, 0, 0));
    EXPECT_EQ(scene.positions[2], vec3(0, 5, 0));
}

TEST(LoaderAttributes, ExtraAttributesLandWithDefaultsForMeshesWithout) {
    GltfDoc doc;
    doc.add_mesh_node({{"attributes", triangle_at(doc, 0)}});
    Json attributes = triangle_at(doc, 10);
    attributes["TEXCOORD_1"] = doc.add_vec2({0.25f, 0.5f, 1, 0, 0, 1});
    const int colours = doc.add_accessor(std::vector<uint8_t>{255, 0, 51, 0, 255, 102, 0, 0, 0}, kUbyte, "VEC3", 3);
    doc.json["accessors"][size_t(colours)]["normalized"] = true;
    attributes["COLOR_0"] = colours;
    attributes["TANGENT"] = doc.add_accessor(std::vector<float>{2, 0, 0, 1, 0, 3, 0, -1, 0, 0, 0, 1}, kFloat,
                                             "VEC4", 4);
    doc.add_mesh_node({{"attributes", attributes}});
    doc.add_mesh_node({{"attributes", triangle_at(doc, 20)}});

    const Scene scene = load_text(doc.text(), "a.gltf");
    ASSERT_EQ(scene.positions.size(), 9u);
    ASSERT_EQ(scene.texcoords1.size(), 9u);
    ASSERT_EQ(scene.colors.size(), 9u);
    ASSERT_EQ(scene.tangents.size(), 9u);
    EXPECT_TRUE(scene.texcoords.empty()) << "no mesh has TEXCOORD_0";
    const vec2 uv1[] = {{0.25f, 0.5f}, {1, 0}, {0, 1}};
    const glm::vec4 colour[] = {{1, 0, 0.2f, 1}, {0, 1, 0.4f, 1}, {0, 0, 0, 1}};
    // The third tangent has no direction: (0, 0, 0, 0), for finalisation to compute.
    const glm::vec4 tangent[] = {{1, 0, 0, 1}, {0, 1, 0, -1}, {0, 0, 0, 0}};
    for (size_t i = 0; i < 9; ++i) {
        const bool second = i >= 3 && i < 6;
        const std::string label = "vertex " + std::to_string(i);
        EXPECT_EQ(scene.texcoords1[i], second ? uv1[i - 3] : vec2(0.0f)) << label;
        expect_near(scene.colors[i], second ? colour[i - 3] : glm::vec4(1.0f), label);
        expect_near(scene.tangents[i], second ? tangent[i - 3] : glm::vec4(0.0f), label);
    }
}

TEST(LoaderAttributes, TangentsTurnWithTheNodeAndFlipWhenItMirrors) {
    GltfDoc doc;
    Json mirrored = triangle_at(doc, 0);
    mirrored["TANGENT"] = doc.add_accessor(std::vector<float>{1, 1, 0, 1, 1, 1, 0, 1, 1, 1, 0, 1}, kFloat, "VEC4", 4);
    doc.add_mesh_node({{"attributes", mirrored}}, {{"scale", {-1, 2, 1}}});
    Json turned = triangle_at(doc, 10);
    // Normalized BYTE tangents (1, 0, 0) with w = -1, turned a quarter about +z.
    const int quantized = doc.add_accessor(std::vector<int8_t>{127, 0, 0, -127, 127, 0, 0, -127, 127, 0, 0, -127},
                                           kByte, "VEC4", 4);
    doc.json["accessors"][size_t(quantized)]["normalized"] = true;
    turned["TANGENT"] = quantized;
    const double s = std::sqrt(0.5);
    doc.add_mesh_node({{"attributes", turned}}, {{"rotation", {0, 0, s, s}}});

    const Scene scene = load_text(doc.text(), "t.gltf");
    ASSERT_EQ(scene.tangents.size(), 6u);
    const glm::vec4 flipped(glm::normalize(vec3(-1, 2, 0)), -1.0f);
    for (size_t i = 0; i < 3; ++i) expect_near(scene.tangents[i], flipped, "mirrored " + std::to_string(i));
    for (size_t i = 3; i < 6; ++i) expect_near(scene.tangents[i], {0, 1, 0, -1}, "turned " + std::to_string(i));
}

TEST(LoaderAttributes, ColoursMayBeFloatVec4OrNormalizedShorts) {
    GltfDoc doc;
    Json floats = triangle_at(doc, 0);
    floats["COLOR_0"] = doc.add_accessor(std::vector<float>{0.5f, 0.25f, 1, 0.5f, 1, 1, 1, 1, 0, 0, 0, 0}, kFloat,
                                         "VEC4", 4);
    doc.add_mesh_node({{"attributes", floats}});
    Json shorts = triangle_at(doc, 10);
    const int colours = doc.add_accessor(std::vector<uint16_t>{65535, 0, 0, 13107, 0, 65535, 0, 0, 0, 0, 65535, 0},
                                         kUshort, "VEC4", 4);
    doc.json["accessors"][size_t(colours)]["normalized"] = true;
    shorts["COLOR_0"] = colours;
    doc.add_mesh_node({{"attributes", shorts}});
    const Scene scene = load_text(doc.text(), "c.gltf");
    ASSERT_EQ(scene.colors.size(), 6u);
    expect_near(scene.colors[0], {0.5f, 0.25f, 1, 0.5f}, "float");
    expect_near(scene.colors[3], {1, 0, 0, 0.2f}, "ushort");
    expect_near(scene.colors[5], {0, 0, 1, 0}, "ushort");

    // Unnormalized integer colours are not allowed.
    doc.json["accessors"][size_t(colours)]["normalized"] = false;
    EXPECT_MENTIONS(scene_error([&] { load_text(doc.text(), "c.gltf"); }),
                    "COLOR_0 (accessors[3]) has UNSIGNED_SHORT components that are not normalized");
}

}  // namespace
}  // namespace rt
