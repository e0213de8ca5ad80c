// What glTF says about a texture beyond its image: KHR_texture_transform and
// texCoord on any textureInfo, the encoding each material slot reads its
// image with, EXT_texture_webp's image, and KHR_texture_basisu refused with
// advice.
#include <gtest/gtest.h>
#include <webp/encode.h>

#include "loader_test_util.h"

namespace rt {
namespace {

using namespace rt::testing;

// A triangle whose material has a 2x2 base colour texture.
GltfDoc textured(const Json& texture_info) {
    GltfDoc doc;
    doc.add_mesh_node({{"attributes", {{"POSITION", doc.add_vec3({0, 0, 0, 1, 0, 0, 0, 1, 0})}}},
                       {"indices", doc.add_indices({0, 1, 2})}});
    const Bytes image = png(2, 2, {255, 0, 0, 0, 255, 0, 0, 0, 255, 128, 128, 128});
    doc.json["images"] = {{{"uri", "data:image/png;base64," + base64(image)}}};
    doc.json["textures"] = {{{"source", 0}}};
    doc.json["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", texture_info}}}}};
    doc.json["meshes"][0]["primitives"][0]["material"] = 0;
    return doc;
}

const Material& first_material(const Scene& scene) { return scene.materials[scene.triangle_materials[0]]; }

TEST(LoaderTexture, TextureTransformAndItsTexCoordAreRead) {
    GltfDoc doc = textured({{"index", 0},
                            {"texCoord", 0},
                            {"extensions",
                             {{"KHR_texture_transform",
                               {{"offset", {0.5, -0.25}}, {"rotation", 1.5}, {"scale", {2, 4}}, {"texCoord", 1}}}}}});
    doc.json["extensionsRequired"] = {"KHR_texture_transform"};
    doc.json["extensionsUsed"] = {"KHR_texture_transform"};
    const Scene scene = load_text(doc.text(), "t.gltf");
    const TextureRef& ref = first_material(scene).base_color_texture;
    EXPECT_EQ(ref.index, 0);
    EXPECT_EQ(ref.texcoord, 1u) << "the transform's texCoord overrides the textureInfo's";
    EXPECT_EQ(ref.transform.offset, vec2(0.5f, -0.25f));
    EXPECT_FLOAT_EQ(ref.transform.rotation, 1.5f);
    EXPECT_EQ(ref.transform.scale, vec2(2.0f, 4.0f));
}

TEST(LoaderTexture, SecondTexCoordIsReadAndAThirdIsIgnored) {
    EXPECT_EQ(first_material(load_text(textured({{"index", 0}, {"texCoord", 1}}).text(), "t.gltf"))
                  .base_color_texture.texcoord,
              1u);
    const Scene scene = load_text(textured({{"index", 0}, {"texCoord", 2}}).text(), "t.gltf");
    EXPECT_FALSE(first_material(scene).base_color_texture);
    EXPECT_TRUE(has_warning(scene, "uses TEXCOORD_2, but only TEXCOORD_0 and TEXCOORD_1 are read"));
}

TEST(LoaderTexture, BadTransformIsRefusedByName) {
    const std::string error = scene_error([] {
        load_text(textured({{"index", 0}, {"extensions", {{"KHR_texture_transform", {{"scale", {1}}}}}}}).text(),
                  "t.gltf");
    });
    EXPECT_TRUE(contains(error, "baseColorTexture.extensions.KHR_texture_transform.scale")) << error;
}

TEST(LoaderTexture, DataMapsAreLinearAndColourIsSrgb) {
    GltfDoc doc = textured({{"index", 0}});
    doc.json["materials"][0]["pbrMetallicRoughness"]["metallicRoughnessTexture"] = {{"index", 0}};
    const Scene scene = load_text(doc.text(), "t.gltf");
    const Material& m = first_material(scene);
    ASSERT_EQ(scene.textures.size(), 2u) << "one image, read two ways";
    const Texture& colour = scene.textures[size_t(m.base_color_texture.index)];
    const Texture& data = scene.textures[size_t(m.metallic_roughness_texture.index)];
    EXPECT_EQ(colour.encoding, Texture::Encoding::Srgb);
    EXPECT_EQ(data.encoding, Texture::Encoding::Linear);
    EXPECT_NEAR(colour.texel(0, 1, 1).r, srgb_to_linear(128.0f / 255.0f), 1e-6f);
    EXPECT_NEAR(data.texel(0, 1, 1).r, 128.0f / 255.0f, 1e-6f);
}

TEST(LoaderTexture, WebpImageOfEXTTextureWebpIsRead) {
    GltfDoc doc = textured({{"index", 0}});
    const uint8_t rgba[] = {10, 20, 30, 40, 50, 60, 70, 80, 90, 100, 110, 120, 130, 140, 150, 5};
    uint8_t* webp = nullptr;
    const size_t size = WebPEncodeLosslessRGBA(rgba, 2, 2, 8, &webp);
    ASSERT_GT(size, 0u);
    const Bytes image(webp, webp + size);
    WebPFree(webp);
    while (doc.data.size() % 4 != 0) doc.data.push_back(0);
    doc.json["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", doc.data.size()}, {"byteLength", image.size()}});
    doc.data.insert(doc.data.end(), image.begin(), image.end());
    // The PNG stays as the fallback for viewers without WebP; we take the WebP.
    doc.json["images"].push_back({{"bufferView", doc.json["bufferViews"].size() - 1}, {"mimeType", "image/webp"}});
    doc.json["textures"] = {{{"source", 0}, {"extensions", {{"EXT_texture_webp", {{"source", 1}}}}}}};
    doc.json["extensionsUsed"] = {"EXT_texture_webp"};
    doc.json["extensionsRequired"] = {"EXT_texture_webp"};
    const Scene scene = load_bytes(doc.glb(), "w.glb");
    ASSERT_EQ(scene.textures.size(), 1u);
    const Texture& t = scene.textures[0];
    EXPECT_EQ(t.channels, 4);
    EXPECT_EQ(t.levels[0].texels, std::vector<uint8_t>(std::begin(rgba), std::end(rgba)))
        << "alpha stays unassociated";
}

TEST(LoaderTexture, BasisuTextureIsRefusedWithAdvice) {
    GltfDoc doc = textured({{"index", 0}});
    doc.json["textures"] = {{{"extensions", {{"KHR_texture_basisu", {{"source", 0}}}}}}};
    const std::string error = scene_error([&] { load_text(doc.text(), "b.gltf"); });
    EXPECT_TRUE(contains(error, "b.gltf: textures[0] has only a KHR_texture_basisu (KTX2) image")) << error;
    EXPECT_TRUE(contains(error, "gltf-transform png")) << error;
    // With a PNG fallback the texture loads from it.
    doc.json["textures"][0]["source"] = 0;
    EXPECT_EQ(load_text(doc.text(), "b.gltf").textures.size(), 1u);
    // A file that requires the extension is refused before anything is read, with the same advice.
    doc.json["extensionsRequired"] = {"KHR_texture_basisu"};
    EXPECT_TRUE(contains(scene_error([&] { load_text(doc.text(), "b.gltf"); }), "gltf-transform png"));
}

}  // namespace
}  // namespace rt
