// glTF 2.0 loading: node transforms, indexed and non-indexed triangles, strips
// and fans, normals, texture coordinates, materials, textures, lights, cameras.
#include <cmath>

#include <gtest/gtest.h>

#include "loader_test_util.h"
#include "load/texture_decode.h"

namespace rt {
namespace {

using namespace rt::testing;

constexpr float kEps = 1e-5f;

void expect_vec3(vec3 actual, vec3 expected, float eps = kEps) {
    EXPECT_NEAR(actual.x, expected.x, eps);
    EXPECT_NEAR(actual.y, expected.y, eps);
    EXPECT_NEAR(actual.z, expected.z, eps);
}

// A unit right triangle in the z = 0 plane.
GltfDoc triangle_doc(const Json& node_fields = Json::object(), bool indexed = true) {
    GltfDoc doc;
    Json primitive = {{"attributes", {{"POSITION", doc.add_vec3({0, 0, 0, 1, 0, 0, 0, 1, 0})}}}};
    if (indexed) primitive["indices"] = doc.add_indices({0, 1, 2});
    doc.add_mesh_node(primitive, node_fields);
    return doc;
}

TEST(LoaderGltf, TranslationRotationScaleGiveWorldPositions) {
    // Scale x by 2, then rotate 90 degrees about +z (x -> y), then translate.
    const float s = std::sqrt(0.5f);
    const Scene scene = load_text(
        triangle_doc({{"translation", {10, 0, 0}}, {"rotation", {0, 0, s, s}}, {"scale", {2, 1, 1}}}).text(), "t.gltf");
    ASSERT_EQ(scene.triangles.size(), 1u);
    const uvec3 t = scene.triangles[0];
    expect_vec3(scene.positions[t.x], {10, 0, 0});
    expect_vec3(scene.positions[t.y], {10, 2, 0});
    expect_vec3(scene.positions[t.z], {9, 0, 0});
}

TEST(LoaderGltf, ChildNodesComposeWithTheirParentsMatrix) {
    GltfDoc doc = triangle_doc();
    // Move the mesh node under a parent whose column-major matrix translates by (0, 0, -5).
    doc.json["scenes"][0]["nodes"] = {1};
    doc.json["nodes"].push_back({{"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, -5, 1}}, {"children", {0}}});
    doc.json["nodes"][0]["translation"] = {1, 1, 0};
    const Scene scene = load_text(doc.text(), "t.gltf");
    ASSERT_EQ(scene.triangles.size(), 1u);
    expect_vec3(scene.positions[scene.triangles[0].x], {1, 1, -5});
    expect_vec3(scene.positions[scene.triangles[0].y], {2, 1, -5});
}

TEST(LoaderGltf, WithoutScenesEveryRootNodeIsShown) {
    GltfDoc doc = triangle_doc();
    doc.json["nodes"].push_back({{"mesh", 0}, {"translation", {0, 0, 3}}});
    doc.json.erase("scene");
    doc.json.erase("scenes");
    const Scene scene = load_text(doc.text(), "t.gltf");
    EXPECT_EQ(scene.placed_triangles(), 2u);
    EXPECT_EQ(scene.instances.size(), 2u) << "both nodes draw mesh 0: one copy, two instances";
}

TEST(LoaderGltf, IndexedAndNonIndexedGiveTheSameTriangle) {
    for (bool indexed : {true, false}) {
        const Scene scene = load_text(triangle_doc(Json::object(), indexed).text(), "t.gltf");
        ASSERT_EQ(scene.triangles.size(), 1u);
        expect_vec3(scene.positions[scene.triangles[0].y], {1, 0, 0});
        expect_vec3(scene.normals[scene.triangles[0].x], {0, 0, 1});
    }
}

TEST(LoaderGltf, MissingNormalsAreAreaWeighted) {
    // Two faces share the edge A-C: one in z = 0 (normal +z, area 0.5) and one in
    // x = 0 (normal -x, area 1). Area weighting gives (-2, 0, 1) / sqrt(5) at A
    // and C; equal weights would give (-1, 0, 1) / sqrt(2).
    GltfDoc doc;
    const int positions = doc.add_vec3({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 2});
    doc.add_mesh_node({{"attributes", {{"POSITION", positions}}}, {"indices", doc.add_indices({0, 1, 2, 0, 3, 2})}});
    const Scene scene = load_text(doc.text(), "n.gltf");
    ASSERT_EQ(scene.triangles.size(), 2u);
    const uvec3 first = scene.triangles[0], second = scene.triangles[1];
    const vec3 shared = glm::normalize(vec3(-2, 0, 1));
    expect_vec3(scene.normals[first.x], shared);   // A
    expect_vec3(scene.normals[first.z], shared);   // C
    expect_vec3(scene.normals[first.y], {0, 0, 1});  // B
    expect_vec3(scene.normals[second.y], {-1, 0, 0});  // D
}

TEST(LoaderGltf, GivenNormalsFollowTheInverseTransposeAndAreNormalised) {
    GltfDoc doc;
    const int positions = doc.add_vec3({0, 0, 0, 1, 0, 0, 0, 1, 0});
    // A normal tilted in x and z; scaling x by 4 must tilt it towards z, not x.
    const int normals = doc.add_vec3({1, 0, 1, 1, 0, 1, 0, 0, 3});
    doc.add_mesh_node({{"attributes", {{"POSITION", positions}, {"NORMAL", normals}}}}, {{"scale", {4, 1, 1}}});
    const Scene scene = load_text(doc.text(), "n.gltf");
    ASSERT_EQ(scene.triangles.size(), 1u);
    expect_vec3(scene.normals[scene.triangles[0].x], glm::normalize(vec3(0.25f, 0, 1)));
    expect_vec3(scene.normals[scene.triangles[0].z], {0, 0, 1});
}

TEST(LoaderGltf, MirroringTransformKeepsWindingAndNormalsAgreeing) {
    GltfDoc doc;
    const int positions = doc.add_vec3({0, 0, 0, 1, 0, 0, 0, 1, 0});
    const int normals = doc.add_vec3({0, 0, 1, 0, 0, 1, 0, 0, 1});
    doc.add_mesh_node({{"attributes", {{"POSITION", positions}, {"NORMAL", normals}}}}, {{"scale", {-1, 1, 1}}});
    const Scene scene = load_text(doc.text(), "m.gltf");
    ASSERT_EQ(scene.triangles.size(), 1u);
    const uvec3 t = scene.triangles[0];
    const vec3 face = glm::normalize(glm::cross(scene.positions[t.y] - scene.positions[t.x],
                                                scene.positions[t.z] - scene.positions[t.x]));
    EXPECT_GT(glm::dot(face, scene.normals[t.x]), 0.99f);
}

TEST(LoaderGltf, StripsAndFansBecomeTrianglesFacingOneWay) {
    for (int mode : {5, 6}) {
        GltfDoc doc;
        // A strip zig-zags along x; a fan turns around its first vertex. All in z = 0.
        const std::vector<float> strip = {0, 0, 0, 0, 1, 0, 1, 0, 0, 1, 1, 0, 2, 0, 0};
        const std::vector<float> fan = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, -1, 1, 0};
        doc.add_mesh_node({{"attributes", {{"POSITION", doc.add_vec3(mode == 5 ? strip : fan)}}}, {"mode", mode}});
        const Scene scene = load_text(doc.text(), "s.gltf");
        ASSERT_EQ(scene.triangles.size(), 3u) << "mode " << mode;
        for (const uvec3& t : scene.triangles) {
            const vec3 n = glm::cross(scene.positions[t.y] - scene.positions[t.x],
                                      scene.positions[t.z] - scene.positions[t.x]);
            EXPECT_EQ(glm::sign(n.z), mode == 5 ? -1.0f : 1.0f) << "mode " << mode;
        }
    }
}

TEST(LoaderGltf, PointsAndLinesAreSkippedWithAWarningNamingThePrimitive) {
    GltfDoc doc = triangle_doc();
    doc.json["meshes"][0]["primitives"].push_back(
        {{"attributes", {{"POSITION", 0}}}, {"mode", 1}});
    const Scene scene = load_text(doc.text(), "l.gltf");
    EXPECT_EQ(scene.triangles.size(), 1u);
    EXPECT_TRUE(has_warning(scene, "meshes[0].primitives[1] has mode LINES"));
}

TEST(LoaderGltf, TexcoordsAreReadAndFilledForMeshesWithout) {
    GltfDoc doc;
    const int positions = doc.add_vec3({0, 0, 0, 1, 0, 0, 0, 1, 0});
    doc.add_mesh_node({{"attributes", {{"POSITION", positions}, {"TEXCOORD_0", doc.add_vec2({0, 0, 1, 0, 0.5f, 1})}}}});
    doc.add_mesh_node({{"attributes", {{"POSITION", positions}}}}, {{"translation", {0, 0, 1}}});
    const Scene scene = load_text(doc.text(), "uv.gltf");
    ASSERT_EQ(scene.texcoords.size(), scene.positions.size());
    ASSERT_EQ(scene.triangles.size(), 2u);
    EXPECT_EQ(scene.texcoords[scene.triangles[0].z], vec2(0.5f, 1.0f));
    EXPECT_EQ(scene.texcoords[scene.triangles[1].z], vec2(0.0f, 0.0f));
}

TEST(LoaderGltf, MetallicRoughnessMapsToPhong) {
    GltfDoc doc = triangle_doc();
    doc.json["materials"] = {
        {{"name", "plastic"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.25, 1, 1}},
                                                         {"metallicFactor", 0}, {"roughnessFactor", 1}}}},
        {{"name", "gold"}, {"pbrMetallicRoughness", {{"baseColorFactor", {1, 0.8, 0.2, 1}},
                                                      {"metallicFactor", 1}, {"roughnessFactor", 0.5}}}},
        {{"name", "mirror"}, {"pbrMetallicRoughness", {{"metallicFactor", 1}, {"roughnessFactor", 0}}}}};
    doc.json["meshes"][0]["primitives"][0]["material"] = 0;
    for (int m : {1, 2}) {
        doc.json["meshes"].push_back(doc.json["meshes"][0]);
        doc.json["meshes"][size_t(m)]["primitives"][0]["material"] = m;
        doc.add_root({{"mesh", m}});
    }
    const Scene scene = load_text(doc.text(), "m.gltf");
    ASSERT_EQ(scene.materials.size(), 3u);
    const Material& plastic = scene.materials[scene.triangle_materials[0]];
    EXPECT_EQ(plastic.name, "plastic");
    expect_vec3(plastic.diffuse, {0.5f, 0.25f, 1.0f});
    expect_vec3(plastic.specular, vec3(0.04f));
    EXPECT_FLOAT_EQ(plastic.shininess, 1.0f);  // 2 / 1 - 2 = 0, clamped to 1
    expect_vec3(plastic.reflectance, vec3(0.0f));

    const Material& gold = scene.materials[scene.triangle_materials[1]];
    expect_vec3(gold.diffuse, vec3(0.0f));
    expect_vec3(gold.specular, {1.0f, 0.8f, 0.2f});
    EXPECT_NEAR(gold.shininess, 30.0f, 1e-3f);  // alpha = 0.25: 2 / 0.0625 - 2
    expect_vec3(gold.reflectance, vec3(1.0f, 0.8f, 0.2f) * 0.25f);

    const Material& mirror = scene.materials[scene.triangle_materials[2]];
    EXPECT_FLOAT_EQ(mirror.shininess, 10000.0f);
    expect_vec3(mirror.reflectance, vec3(1.0f));
}

TEST(LoaderGltf, PrimitivesWithoutMaterialAreNeutralGrey) {
    const Scene scene = load_text(triangle_doc().text(), "t.gltf");
    ASSERT_EQ(scene.materials.size(), 1u);
    const Material& grey = scene.materials[scene.triangle_materials[0]];
    expect_vec3(grey.diffuse, vec3(0.8f));
    expect_vec3(grey.specular, vec3(0.0f));
    expect_vec3(grey.reflectance, vec3(0.0f));
}

// A 2x2 texture: red, green / blue, sRGB 128 grey.
GltfDoc textured_doc(int wrap_s, int wrap_t) {
    GltfDoc doc = triangle_doc();
    const Bytes image = png(2, 2, {255, 0, 0, 0, 255, 0, 0, 0, 255, 128, 128, 128});
    doc.json["images"] = {{{"uri", "data:image/png;base64," + base64(image)}}};
    doc.json["samplers"] = {{{"wrapS", wrap_s}, {"wrapT", wrap_t}}};
    doc.json["textures"] = {{{"source", 0}, {"sampler", 0}}};
    doc.json["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}},
                                                        {"metallicFactor", 0}}}}};
    doc.json["meshes"][0]["primitives"][0]["material"] = 0;
    return doc;
}

TEST(LoaderGltf, BaseColourTextureIsDecodedFromSrgbAndSampledBilinearly) {
    const Scene scene = load_text(textured_doc(10497, 33071).text(), "tex.gltf");
    ASSERT_EQ(scene.textures.size(), 1u);
    const Material& material = scene.materials[scene.triangle_materials[0]];
    ASSERT_EQ(material.base_color_texture.index, 0);
    const Texture& texture = scene.textures[0];
    EXPECT_EQ(texture.wrap_s, Texture::Wrap::Repeat);
    EXPECT_EQ(texture.wrap_t, Texture::Wrap::ClampToEdge);
    const float grey = srgb_to_linear(128.0f / 255.0f);
    EXPECT_NEAR(grey, 0.2158605f, 1e-5f);
    // Texel centres, then half way between texels.
    expect_vec3(vec3(texture.sample({0.25f, 0.25f})), {1, 0, 0});
    expect_vec3(vec3(texture.sample({0.75f, 0.75f})), vec3(grey));
    expect_vec3(vec3(texture.sample({0.5f, 0.25f})), {0.5f, 0.5f, 0});
    expect_vec3(vec3(texture.sample({0.5f, 0.5f})), vec3(0.25f + 0.25f * grey));
    // Repeat in s wraps texel 1 onto texel 0; clamp in t does not wrap.
    expect_vec3(vec3(texture.sample({0.0f, 0.25f})), {0.5f, 0.5f, 0});
    expect_vec3(vec3(texture.sample({0.25f, 0.0f})), {1, 0, 0});
}

TEST(LoaderGltf, MirroredRepeatSamplerIsKept) {
    const Scene scene = load_text(textured_doc(33648, 33648).text(), "tex.gltf");
    ASSERT_EQ(scene.textures.size(), 1u);
    EXPECT_EQ(scene.textures[0].wrap_s, Texture::Wrap::MirroredRepeat);
    // u = 1.25 mirrors back onto texel 1 (green); Repeat would give texel 0.
    expect_vec3(vec3(scene.textures[0].sample({1.25f, 0.25f})), {0, 1, 0});
}

TEST(LoaderGltf, TextureInABufferViewOfAGlb) {
    GltfDoc doc = textured_doc(10497, 10497);
    const Bytes image = png(2, 2, {255, 0, 0, 0, 255, 0, 0, 0, 255, 128, 128, 128});
    while (doc.data.size() % 4 != 0) doc.data.push_back(0);
    doc.json["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", doc.data.size()}, {"byteLength", image.size()}});
    doc.data.insert(doc.data.end(), image.begin(), image.end());
    doc.json["images"] = {{{"bufferView", doc.json["bufferViews"].size() - 1}, {"mimeType", "image/png"}}};
    const Scene scene = load_bytes(doc.glb(), "tex.glb");
    ASSERT_EQ(scene.textures.size(), 1u);
    expect_vec3(vec3(scene.textures[0].sample({0.75f, 0.25f})), {0, 1, 0});
}

TEST(LoaderGltf, PunctualLightsTakeTheirNodesPosition) {
    GltfDoc doc = triangle_doc();
    doc.json["extensionsUsed"] = {"KHR_lights_punctual"};
    doc.json["extensionsRequired"] = {"KHR_lights_punctual"};
    doc.json["extensions"]["KHR_lights_punctual"]["lights"] = {
        {{"type", "point"}, {"name", "bulb"}, {"color", {1, 0.5, 0.25}}, {"intensity", 8}},
        {{"type", "spot"}, {"range", 5}, {"spot", {{"innerConeAngle", 0.25}, {"outerConeAngle", 0.5}}}},
        {{"type", "directional"}, {"intensity", 3}, {"extras", {{"rt", {{"angular_diameter", 2}}}}}}};
    const Json light = {{"KHR_lights_punctual", {{"light", 0}}}};
    doc.json["nodes"].push_back({{"translation", {0, 4, 0}}, {"extensions", light}});
    doc.add_root({{"translation", {1, 2, 3}}, {"children", {int(doc.json["nodes"].size() - 1)}}});
    doc.add_root({{"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
    // Turned a quarter about +X: its -Z becomes -Y, straight down.
    const double h = std::sqrt(0.5);
    doc.add_root({{"rotation", {-h, 0, 0, h}}, {"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}});
    const Scene scene = load_text(doc.text(), "l.gltf");
    ASSERT_EQ(scene.lights.size(), 3u);
    EXPECT_EQ(scene.lights[0].name, "bulb");
    expect_vec3(scene.lights[0].position, {1, 6, 3});
    expect_vec3(scene.lights[0].intensity, {8, 4, 2});
    EXPECT_EQ(scene.lights[0].radius, 0.0f);
    EXPECT_TRUE(scene.lights[0].plain_point());
    EXPECT_EQ(scene.lights[1].kind, SPOT);
    expect_vec3(scene.lights[1].direction, {0, 0, -1});
    EXPECT_FLOAT_EQ(scene.lights[1].cos_inner, std::cos(0.25f));
    EXPECT_FLOAT_EQ(scene.lights[1].cos_outer, std::cos(0.5f));
    EXPECT_EQ(scene.lights[1].range, 5.0f);
    EXPECT_EQ(scene.lights[2].kind, DIRECTIONAL);
    expect_vec3(scene.lights[2].direction, {0, -1, 0});
    EXPECT_NEAR(scene.lights[2].angular_diameter, 2.0f * kPi / 180.0f, 1e-6f);
    EXPECT_EQ(scene.rig_lights, 0u);
    EXPECT_TRUE(scene.warnings.empty());
}

TEST(LoaderGltf, PerspectiveCamerasLookDownTheirNodesMinusZ) {
    GltfDoc doc = triangle_doc();
    doc.json["cameras"] = {{{"type", "perspective"}, {"name", "side"},
                            {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}}};
    const float s = std::sqrt(0.5f);  // 90 degrees about +y: -z turns into -x
    doc.add_root({{"camera", 0}, {"translation", {0, 1, 5}}, {"rotation", {0, s, 0, s}}});
    const Scene scene = load_text(doc.text(), "c.gltf");
    ASSERT_EQ(scene.cameras.size(), 1u);
    const SceneCamera& camera = scene.cameras[0];
    EXPECT_EQ(camera.name, "side");
    ASSERT_EQ(camera.camera.position_size(), 3);
    expect_vec3({camera.camera.position(0), camera.camera.position(1), camera.camera.position(2)}, {0, 1, 5});
    expect_vec3({camera.camera.target(0), camera.camera.target(1), camera.camera.target(2)}, {-1, 1, 5});
    expect_vec3({camera.camera.up(0), camera.camera.up(1), camera.camera.up(2)}, {0, 1, 0});
    EXPECT_NEAR(camera.camera.fov_y(), 0.5f * 180.0f / kPi, 1e-4f);
}

TEST(LoaderGltf, GlbWithBinChunkLoads) {
    const Scene scene = load_bytes(triangle_doc({{"translation", {0, 0, 2}}}).glb(), "t.glb");
    ASSERT_EQ(scene.triangles.size(), 1u);
    expect_vec3(scene.positions[scene.triangles[0].y], {1, 0, 2});
}

TEST(LoaderGltf, ExternalBufferAndImageInsideTheFolderLoad) {
    TempDir dir;
    GltfDoc doc = textured_doc(10497, 10497);
    dir.write("data/mesh.bin", doc.data);
    dir.write("textures/albedo.png", png(2, 2, {255, 0, 0, 0, 255, 0, 0, 0, 255, 128, 128, 128}));
    Json json = doc.json;
    json["buffers"] = {{{"byteLength", doc.data.size()}, {"uri", "data/mesh.bin"}}};
    json["images"] = {{{"uri", "textures/../textures/albedo.png"}}};
    const Scene scene = load_scene(dir.write("scene.gltf", json.dump()));
    EXPECT_EQ(scene.triangles.size(), 1u);
    EXPECT_EQ(scene.textures.size(), 1u);
}

TEST(LoaderGltf, UnsupportedRequiredExtensionIsRefusedByName) {
    GltfDoc doc = triangle_doc();
    doc.json["extensionsRequired"] = {"KHR_materials_pbrSpecularGlossiness"};
    EXPECT_TRUE(contains(scene_error([&] { load_text(doc.text(), "d.gltf"); }),
                         "'KHR_materials_pbrSpecularGlossiness'"));
}

}  // namespace
}  // namespace rt
