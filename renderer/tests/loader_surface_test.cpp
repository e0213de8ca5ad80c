// glTF's surface inputs as the loader reads them: emission with
// KHR_materials_emissive_strength, alphaMode and alphaCutoff, doubleSided,
// and the maps that vary the metallic-roughness terms; bad values are refused
// by name.
#include <gtest/gtest.h>

#include "loader_test_util.h"

namespace rt {
namespace {

using namespace rt::testing;

GltfDoc material_doc(const Json& material) {
    GltfDoc doc;
    Json primitive = {{"attributes", {{"POSITION", doc.add_vec3({0, 0, 0, 1, 0, 0, 0, 1, 0})}}}, {"material", 0}};
    doc.add_mesh_node(primitive);
    doc.json["materials"] = {material};
    return doc;
}

// A copy: the scene it came from is often a temporary.
Material only_material(const Scene& scene) { return scene.materials[scene.triangle_materials[0]]; }

TEST(LoaderSurface, EmissionIsTheFactorTimesTheStrength) {
    GltfDoc doc = material_doc({{"emissiveFactor", {1.0, 0.5, 0.0}},
                                {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4.0}}}}}});
    doc.json["extensionsUsed"] = {"KHR_materials_emissive_strength"};
    doc.json["extensionsRequired"] = {"KHR_materials_emissive_strength"};
    const Material& m = only_material(load_text(doc.text(), "e.gltf"));
    EXPECT_EQ(m.emission, vec3(4.0f, 2.0f, 0.0f));
    EXPECT_TRUE(m.metallic_roughness);
}

TEST(LoaderSurface, WithoutEmissionAMaterialEmitsNothing) {
    const Material& m = only_material(load_text(material_doc({{"name", "plain"}}).text(), "e.gltf"));
    EXPECT_EQ(m.emission, vec3(0.0f));
    EXPECT_EQ(m.alpha_mode, AlphaMode::Opaque);
    EXPECT_FALSE(m.double_sided);
}

TEST(LoaderSurface, AlphaModeCutoffAndBaseAlphaAreRead) {
    const Material& mask = only_material(load_text(
        material_doc({{"alphaMode", "MASK"}, {"alphaCutoff", 0.3}, {"doubleSided", true},
                      {"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 0.6}}}}})
            .text(),
        "a.gltf"));
    EXPECT_EQ(mask.alpha_mode, AlphaMode::Mask);
    EXPECT_FLOAT_EQ(mask.alpha_cutoff, 0.3f);
    EXPECT_FLOAT_EQ(mask.alpha, 0.6f);
    EXPECT_TRUE(mask.double_sided);
    const Material& blend = only_material(load_text(material_doc({{"alphaMode", "BLEND"}}).text(), "b.gltf"));
    EXPECT_EQ(blend.alpha_mode, AlphaMode::Blend);
    EXPECT_FLOAT_EQ(blend.alpha_cutoff, 0.5f);  // the specification's default
}

TEST(LoaderSurface, BadValuesAreRefusedByName) {
    const std::string mode = scene_error([] { load_text(material_doc({{"alphaMode", "CLEAR"}}).text(), "a.gltf"); });
    EXPECT_TRUE(contains(mode, "materials[0].alphaMode is")) << mode;
    EXPECT_TRUE(contains(mode, "CLEAR")) << mode;
    EXPECT_TRUE(contains(scene_error([] { load_text(material_doc({{"alphaCutoff", -1}}).text(), "a.gltf"); }),
                         "materials[0].alphaCutoff is -1"));
    GltfDoc strength = material_doc(
        {{"emissiveFactor", {1, 1, 1}}, {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", -2}}}}}});
    EXPECT_TRUE(contains(scene_error([&] { load_text(strength.text(), "e.gltf"); }), "emissiveStrength is -2"));
}

}  // namespace
}  // namespace rt
