// The sidecar `<scene>.rt.json` and glTF `extras.rt` (rt.SceneExtras): merged
// into the scene, and validated against the schema's limits.
#include <cmath>

#include <gtest/gtest.h>

#include "loader_test_util.h"

namespace rt {
namespace {

using namespace rt::testing;

const std::string kTriangleObj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

void expect_vec3(vec3 actual, vec3 expected) {
    EXPECT_NEAR(actual.x, expected.x, 1e-6f);
    EXPECT_NEAR(actual.y, expected.y, 1e-6f);
    EXPECT_NEAR(actual.z, expected.z, 1e-6f);
}

TEST(LoaderExtras, SidecarAddsSpheresLightsBackgroundAndCameras) {
    const Scene scene = load_scene(RT_TEST_DATA_DIR "/quads.obj");
    ASSERT_EQ(scene.spheres.size(), 1u);
    const Sphere& sphere = scene.spheres[0];
    expect_vec3(sphere.center, {0.5f, 0.5f, 0.5f});
    EXPECT_FLOAT_EQ(sphere.radius, 0.25f);
    ASSERT_LT(sphere.material, scene.materials.size());
    const Material& material = scene.materials[sphere.material];
    expect_vec3(material.diffuse, {0.2f, 0.3f, 0.4f});
    expect_vec3(material.specular, vec3(0.5f));
    EXPECT_FLOAT_EQ(material.shininess, 64.0f);

    ASSERT_EQ(scene.lights.size(), 1u);
    expect_vec3(scene.lights[0].position, {0, 2, 2});
    expect_vec3(scene.lights[0].intensity, {10, 5, 5});  // colour times intensity
    EXPECT_FLOAT_EQ(scene.lights[0].radius, 0.1f);
    EXPECT_EQ(scene.background, Background(vec3(0.1f, 0.2f, 0.3f)));

    ASSERT_EQ(scene.cameras.size(), 1u);
    EXPECT_EQ(scene.cameras[0].name, "front");
    EXPECT_FLOAT_EQ(scene.cameras[0].camera.position(2), 3.0f);
    EXPECT_FLOAT_EQ(scene.cameras[0].camera.fov_y(), 45.0f);  // the schema's default
    EXPECT_FALSE(has_warning(scene, "no lights"));
}

TEST(LoaderExtras, SchemaDefaultsFillWhatTheSidecarLeavesOut) {
    TempDir dir;
    dir.write("s.rt.json", R"({"spheres": [{"center": [0, 0, 0], "radius": 1}], "lights": [{"position": [0, 1, 0]}]})");
    const Scene scene = load_scene(dir.write("s.obj", kTriangleObj));
    ASSERT_EQ(scene.spheres.size(), 1u);
    const Material& material = scene.materials[scene.spheres[0].material];
    expect_vec3(material.diffuse, vec3(0.8f));
    EXPECT_FLOAT_EQ(material.shininess, 32.0f);
    ASSERT_EQ(scene.lights.size(), 1u);
    expect_vec3(scene.lights[0].intensity, vec3(1.0f));
    EXPECT_EQ(scene.lights[0].radius, 0.0f);
}

TEST(LoaderExtras, SpotAndDirectionalLightsTakeTheirShape) {
    TempDir dir;
    dir.write("s.rt.json", R"({"lights": [
        {"kind": "SPOT", "position": [0, 3, 0], "direction": [0, -2, 0], "inner_cone_angle": 10,
         "outer_cone_angle": 30, "range": 8},
        {"kind": "DIRECTIONAL", "direction": [1, -1, 0], "intensity": 2, "angular_diameter": 0.53}]})");
    const std::filesystem::path file = dir.write("s.obj", kTriangleObj);
    const Scene scene = load_scene(file);
    ASSERT_EQ(scene.lights.size(), 2u);
    EXPECT_EQ(scene.lights[0].kind, SPOT);
    expect_vec3(scene.lights[0].direction, {0, -1, 0});
    EXPECT_FLOAT_EQ(scene.lights[0].cos_inner, std::cos(10.0f * kPi / 180.0f));
    EXPECT_FLOAT_EQ(scene.lights[0].cos_outer, std::cos(30.0f * kPi / 180.0f));
    EXPECT_EQ(scene.lights[0].range, 8.0f);
    EXPECT_EQ(scene.lights[1].kind, DIRECTIONAL);
    expect_vec3(scene.lights[1].direction, glm::normalize(vec3(1, -1, 0)));
    EXPECT_FLOAT_EQ(scene.lights[1].angular_diameter, 0.53f * kPi / 180.0f);
    EXPECT_EQ(scene.rig_lights, 0u);
    // What each kind needs, by name.
    dir.write("s.rt.json", R"({"lights": [{"kind": "SPOT"}]})");
    EXPECT_TRUE(contains(scene_error([&] { load_scene(file); }), "extras.lights[0].position: is required"));
    dir.write("s.rt.json", R"({"lights": [{"kind": "SPOT", "position": [0, 0, 0], "radius": 1}]})");
    EXPECT_TRUE(contains(scene_error([&] { load_scene(file); }), "extras.lights[0].radius: only point lights"));
    dir.write("s.rt.json", R"({"lights": [{"kind": "SPOT", "position": [0, 0, 0], "inner_cone_angle": 50}]})");
    EXPECT_TRUE(contains(scene_error([&] { load_scene(file); }), "inner_cone_angle: must be below"));
    dir.write("s.rt.json", R"({"lights": [{"kind": "DIRECTIONAL", "direction": [0, 0, 0]}]})");
    EXPECT_TRUE(contains(scene_error([&] { load_scene(file); }), "extras.lights[0].direction: is zero"));
}

TEST(LoaderExtras, GltfExtrasOnTheAssetAndTheSceneAreMerged) {
    const Scene scene = load_scene(RT_TEST_DATA_DIR "/triangle.gltf");
    EXPECT_EQ(scene.background, Background(vec3(0.5f)));  // asset.extras.rt
    ASSERT_EQ(scene.lights.size(), 1u);           // the KHR_lights_punctual lamp
    EXPECT_EQ(scene.lights[0].name, "lamp");

    GltfDoc doc;
    doc.add_mesh_node({{"attributes", {{"POSITION", doc.add_vec3({0, 0, 0, 1, 0, 0, 0, 1, 0})}}}});
    doc.json["asset"]["extras"]["rt"] = {{"background", {1, 1, 1}}};
    const Json sphere = {{"center", {0, 0, 0}}, {"radius", 2}};
    doc.json["scenes"][0]["extras"]["rt"] = {{"background", {0, 0, 1}}, {"spheres", {sphere}}};
    const Scene merged = load_text(doc.text(), "e.gltf");
    EXPECT_EQ(merged.background, Background(vec3(0, 0, 1)));  // the scene's extras come after the asset's
    EXPECT_EQ(merged.spheres.size(), 1u);
}

TEST(LoaderExtras, UnknownFieldsAreRefusedByName) {
    TempDir dir;
    dir.write("s.rt.json", R"({"spheres": [{"radus": 1}]})");
    const std::string error = scene_error([&] { load_scene(dir.write("s.obj", kTriangleObj)); });
    EXPECT_TRUE(contains(error, "s.rt.json") && contains(error, "radus")) << error;
}

TEST(LoaderExtras, ValuesOutsideTheLimitsNameTheField) {
    TempDir dir;
    const std::filesystem::path scene = dir.write("s.obj", kTriangleObj);
    dir.write("s.rt.json", R"({"spheres": [{"center": [0, 0, 0], "radius": -1}]})");
    EXPECT_EQ(scene_error([&] { load_scene(scene); }),
              "s.rt.json: extras.spheres[0].radius: -1 is below the minimum 1e-30");
    dir.write("s.rt.json", R"({"lights": [{"position": [0, 1]}]})");
    EXPECT_EQ(scene_error([&] { load_scene(scene); }), "s.rt.json: extras.lights[0].position: needs 3 values, got 2");
    dir.write("s.rt.json", R"({"background": [0, "NaN", 0]})");
    EXPECT_EQ(scene_error([&] { load_scene(scene); }), "s.rt.json: extras.background[1]: must be a finite number");
    dir.write("s.rt.json", R"({"lights": [{"position": [0, 0, 0], "color": [3e38, 1, 1], "intensity": 1e29}]})");
    EXPECT_TRUE(contains(scene_error([&] { load_scene(scene); }), "extras.lights[0]: color times intensity"));
    dir.write("s.rt.json", R"({"spheres": [{"radius": 1}]})");
    EXPECT_EQ(scene_error([&] { load_scene(scene); }), "s.rt.json: extras.spheres[0].center: is required");
    dir.write("s.rt.json", R"({"cameras": [{"name": "empty"}]})");
    EXPECT_EQ(scene_error([&] { load_scene(scene); }), "s.rt.json: extras.cameras[0].camera.position: is required");
    dir.write("s.rt.json", "{");
    EXPECT_TRUE(contains(scene_error([&] { load_scene(scene); }), "s.rt.json: extras: invalid JSON"));
}

TEST(LoaderExtras, GltfExtrasAreValidatedWithTheirPath) {
    GltfDoc doc;
    const Json camera = {{"position", {0, 0, 1}}, {"target", {0, 0, 0}}, {"up", {0, 1, 0}}, {"fovY", 500}};
    doc.json["asset"]["extras"]["rt"] = {{"cameras", {{{"camera", camera}}}}};
    EXPECT_EQ(scene_error([&] { load_text(doc.text(), "e.gltf"); }),
              "e.gltf: asset.extras.rt.cameras[0].camera.fov_y: 500 is above the maximum 179");
    doc.json["asset"]["extras"]["rt"] = "not an object";
    EXPECT_EQ(scene_error([&] { load_text(doc.text(), "e.gltf"); }), "e.gltf: asset.extras.rt must be a JSON object");
}

}  // namespace
}  // namespace rt
