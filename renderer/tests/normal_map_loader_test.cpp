// A glTF (and an OBJ) normal map through the loader and model.glb: normalTexture and its
// scale read, the image kept linear, MikkTSpace tangents for a mesh without
// TANGENT, and both written to the export, which loads back the same.
#include <cstring>

#include <gtest/gtest.h>

#include "export/glb_export.h"
#include "loader_test_util.h"

namespace rt {
namespace {

using namespace rt::testing;

Json glb_json(const std::string& glb) {
    uint32_t length = 0;
    std::memcpy(&length, glb.data() + 12, 4);
    return Json::parse(glb.substr(20, length));
}

// A square in z = 0 facing +z with glTF's uv (v down the image), its
// material normal-mapped by a 1x1 image of code `texel`, no TANGENT.
GltfDoc mapped_square(const Json& normal_texture, std::vector<unsigned char> texel) {
    GltfDoc doc;
    doc.add_mesh_node({{"attributes",
                        {{"POSITION", doc.add_vec3({-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0})},
                         {"NORMAL", doc.add_vec3({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1})},
                         {"TEXCOORD_0", doc.add_vec2({0, 1, 1, 1, 1, 0, 0, 0})}}},
                       {"indices", doc.add_indices({0, 1, 2, 0, 2, 3})},
                       {"material", 0}});
    doc.json["images"] = {{{"uri", "data:image/png;base64," + base64(png(1, 1, texel))}}};
    doc.json["textures"] = {{{"source", 0}}};
    doc.json["materials"] = {{{"normalTexture", normal_texture}}};
    return doc;
}

TEST(NormalMapLoader, NormalTextureIsReadLinearWithItsScale) {
    const Scene scene = load_text(mapped_square({{"index", 0}, {"scale", 0.7}}, {200, 60, 230}).text(), "n.gltf");
    const Material& m = scene.materials[scene.triangle_materials[0]];
    ASSERT_TRUE(m.normal_texture);
    EXPECT_FLOAT_EQ(m.normal_scale, 0.7f);
    const Texture& texture = scene.textures[size_t(m.normal_texture.index)];
    EXPECT_EQ(texture.encoding, Texture::Encoding::Linear);
    EXPECT_NEAR(texture.sample({0.5f, 0.5f}).r, 200.0f / 255.0f, 1e-6f);  // sRGB would give 0.58
    // MikkTSpace's tangents, in glTF's convention: T = +x, B = cross(N, T) = +y, up the image.
    ASSERT_EQ(scene.tangents.size(), scene.positions.size());
    for (const glm::vec4& t : scene.tangents) {
        EXPECT_NEAR(glm::distance(vec3(t), vec3(1.0f, 0.0f, 0.0f)), 0.0f, 1e-6f);
        EXPECT_EQ(t.w, 1.0f);
    }
    EXPECT_EQ(load_text(mapped_square({{"index", 0}}, {128, 128, 255}).text(), "n.gltf").materials[0].normal_scale,
              1.0f);  // glTF's default
}

TEST(NormalMapLoader, BadNormalTexturesAreRefusedOrIgnored) {
    std::string text = mapped_square({{"index", 0}, {"scale", 1.0}}, {128, 128, 255}).text();
    const std::string from = "\"scale\":1.0";
    ASSERT_NE(text.find(from), std::string::npos);
    text.replace(text.find(from), from.size(), "\"scale\":1e400");
    // JSON cannot hold an infinite scale: the parser refuses the overflow.
    EXPECT_TRUE(contains(scene_error([&] { load_text(text, "n.gltf"); }), "number overflow"));
    // A huge finite one is clamped to 1e4, where the tilt no longer changes.
    const Scene huge = load_text(mapped_square({{"index", 0}, {"scale", -1e300}}, {128, 128, 255}).text(), "n.gltf");
    EXPECT_EQ(huge.materials[0].normal_scale, -1e4f);
    const std::string missing = mapped_square({{"index", 3}}, {128, 128, 255}).text();
    EXPECT_TRUE(contains(scene_error([&] { load_text(missing, "n.gltf"); }), "normalTexture refers to texture 3"));
    // A map on a texture coordinate set the mesh lacks: shaded without it, said so.
    const Scene scene = load_text(mapped_square({{"index", 0}, {"texCoord", 1}}, {128, 128, 255}).text(), "n.gltf");
    EXPECT_TRUE(scene.tangents.empty());
    EXPECT_TRUE(has_warning(scene, "normal texture reads texture coordinates"));
}

TEST(NormalMapLoader, ExportCarriesTheMapItsScaleAndTheTangents) {
    const Scene scene = load_text(mapped_square({{"index", 0}, {"scale", 0.7}}, {200, 60, 230}).text(), "n.gltf");
    const std::string glb = export_glb(scene);
    const Json doc = glb_json(glb);
    const Json& material = doc["materials"][0];
    ASSERT_TRUE(material.contains("normalTexture"));
    EXPECT_FLOAT_EQ(material["normalTexture"]["scale"].get<float>(), 0.7f);
    const Json& attributes = doc["meshes"][0]["primitives"][0]["attributes"];
    ASSERT_TRUE(attributes.contains("TANGENT"));
    EXPECT_EQ(doc["accessors"][attributes["TANGENT"].get<size_t>()]["type"], "VEC4");

    const Scene back = load_scene_from_memory(std::as_bytes(std::span(glb.data(), glb.size())), "exported.glb");
    const Material& m = back.materials[back.triangle_materials[0]];
    ASSERT_TRUE(m.normal_texture);
    EXPECT_FLOAT_EQ(m.normal_scale, 0.7f);
    EXPECT_EQ(back.textures[size_t(m.normal_texture.index)].encoding, Texture::Encoding::Linear);
    ASSERT_EQ(back.tangents.size(), back.positions.size());
    for (const glm::vec4& t : back.tangents) {
        EXPECT_NEAR(glm::distance(vec3(t), vec3(1.0f, 0.0f, 0.0f)), 0.0f, 1e-6f);
        EXPECT_EQ(t.w, 1.0f);
    }
}

// MTL's `norm` (with -bm as the scale) is the same map; OBJ's v runs up the
// image and is flipped on load, so the tangent frame comes out as glTF's.
TEST(NormalMapLoader, ObjNormIsANormalMapWithTangents) {
    TempDir dir;
    dir.write("n.png", png(1, 1, {200, 60, 230}));
    dir.write("m.mtl", "newmtl bumpy\nKd 0.5 0.5 0.5\nnorm -bm 0.5 n.png\n");
    const Scene scene = load_scene(dir.write("n.obj", "mtllib m.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"
                                                       "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
                                                       "usemtl bumpy\nf 1/1/1 2/2/1 3/3/1 4/4/1\n"));
    const Material& m = scene.materials[scene.triangle_materials[0]];
    ASSERT_TRUE(m.normal_texture);
    EXPECT_FLOAT_EQ(m.normal_scale, 0.5f);
    EXPECT_EQ(scene.textures[size_t(m.normal_texture.index)].encoding, Texture::Encoding::Linear);
    ASSERT_EQ(scene.tangents.size(), scene.positions.size());
    for (const glm::vec4& t : scene.tangents) {
        EXPECT_NEAR(glm::distance(vec3(t), vec3(1.0f, 0.0f, 0.0f)), 0.0f, 1e-6f);
        EXPECT_EQ(t.w, 1.0f);
    }
}

}  // namespace
}  // namespace rt
