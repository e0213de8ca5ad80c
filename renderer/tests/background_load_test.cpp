// A scene's background from its sidecar or glTF extras.rt, beside the default
// rig's sky, and carried through model.glb (export/glb_export.h).
#include <gtest/gtest.h>

#include "export/glb_export.h"
#include "load/light_rig.h"
#include "loader_test_util.h"

namespace rt {
namespace {

using namespace rt::testing;

const std::string kTriangleObj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
const std::string kLight = R"("lights": [{"position": [0, 1, 1]}])";

// The JSON chunk of a GLB.
Json glb_json(const std::string& glb) {
    uint32_t length = 0;
    std::memcpy(&length, glb.data() + 12, 4);
    return Json::parse(glb.substr(20, length));
}

TEST(BackgroundLoad, SidecarGivesAGradient) {
    TempDir dir;
    dir.write("s.rt.json", "{" + kLight + R"(, "background_gradient": {"bottom": [0.1, 0.2, 0.3],
                                              "horizon": [1, 1, 1], "top": [0, 0, 2]}})");
    const Scene scene = load_scene(dir.write("s.obj", kTriangleObj));
    EXPECT_EQ(scene.background, Background({0.1f, 0.2f, 0.3f}, vec3(1.0f), {0.0f, 0.0f, 2.0f}));

    dir.write("s.rt.json", "{" + kLight + R"(, "background_gradient": {"bottom": [0, 0, 0], "top": [1, 1, 1]}})");
    EXPECT_EQ(load_scene(dir.path() / "s.obj").background, Background::ramp(vec3(0.0f), vec3(1.0f)));
}

TEST(BackgroundLoad, BadBackgroundsNameTheField) {
    TempDir dir;
    const std::filesystem::path scene = dir.write("s.obj", kTriangleObj);
    dir.write("s.rt.json",
              R"({"background": [1, 1, 1], "background_gradient": {"bottom": [0, 0, 0], "top": [1, 1, 1]}})");
    EXPECT_EQ(scene_error([&] { load_scene(scene); }),
              "s.rt.json: extras.background_gradient: give background or background_gradient, not both");
    dir.write("s.rt.json", R"({"background_gradient": {"bottom": [0, 0, 0]}})");
    EXPECT_EQ(scene_error([&] { load_scene(scene); }), "s.rt.json: extras.background_gradient.top: is required");
    dir.write("s.rt.json", R"({"background_gradient": {"bottom": [0, 0, 0], "top": [1, -1, 1]}})");
    EXPECT_EQ(scene_error([&] { load_scene(scene); }),
              "s.rt.json: extras.background_gradient.top[1]: -1 is below the minimum 0");
    dir.write("s.rt.json", R"({"background": [1, 1, 1e7]})");
    EXPECT_EQ(scene_error([&] { load_scene(scene); }),
              "s.rt.json: extras.background[2]: 1e+07 is above the maximum 1e+06");
}

// The sidecar comes after the glTF's extras.rt, so its solid colour replaces
// the file's gradient.
TEST(BackgroundLoad, ALaterSourceReplacesAnEarlierOne) {
    GltfDoc doc;
    doc.add_mesh_node({{"attributes", {{"POSITION", doc.add_vec3({0, 0, 0, 1, 0, 0, 0, 1, 0})}}}});
    doc.json["scenes"][0]["extras"]["rt"] = {
        {"background_gradient", {{"bottom", {0, 0, 0}}, {"top", {1, 1, 1}}}}};
    TempDir dir;
    const std::filesystem::path file = dir.write("s.gltf", doc.text());
    EXPECT_EQ(load_scene(file).background, Background::ramp(vec3(0.0f), vec3(1.0f)));
    dir.write("s.rt.json", R"({"background": [0.5, 0.25, 0]})");
    EXPECT_EQ(load_scene(file).background, Background(vec3(0.5f, 0.25f, 0.0f)));
}

// Under the default rig, misses see its sky unless the scene gives a background.
TEST(BackgroundLoad, TheRigsSkyGivesWayToTheScenes) {
    TempDir dir;
    const std::filesystem::path file = dir.write("s.obj", kTriangleObj);
    const Scene plain = load_scene(file);
    ASSERT_EQ(plain.rig_lights, 2u);
    EXPECT_EQ(plain.rig_background, Background(kRigSky));
    EXPECT_TRUE(plain.background.black());

    dir.write("s.rt.json", R"({"background_gradient": {"bottom": [0, 0, 0], "top": [0, 0, 1]}})");
    const Scene given = load_scene(file);
    ASSERT_EQ(given.rig_lights, 2u);
    EXPECT_EQ(given.rig_background, given.background);
    EXPECT_EQ(given.background, Background::ramp(vec3(0.0f), {0.0f, 0.0f, 1.0f}));
}

TEST(BackgroundLoad, ModelGlbCarriesTheBackgroundAndTheRigsSky) {
    TempDir dir;
    const std::filesystem::path file = dir.write("s.obj", kTriangleObj);
    const Json plain = glb_json(export_glb(load_scene(file)));
    EXPECT_EQ(plain["scenes"][0]["extras"]["rt"]["background"], Json::array({0.0f, 0.0f, 0.0f}));
    EXPECT_EQ(plain["scenes"][0]["extras"]["rt_default_rig"]["background"],
              Json::array({kRigSky.x, kRigSky.y, kRigSky.z}));

    dir.write("s.rt.json", "{" + kLight + R"(, "background_gradient": {"bottom": [0, 0, 0], "top": [0, 0, 1]}})");
    const Scene lit = load_scene(file);
    const std::string glb = export_glb(lit);
    const Json json = glb_json(glb);
    EXPECT_FALSE(json["scenes"][0]["extras"].contains("rt_default_rig"));  // lights of its own: no rig
    EXPECT_EQ(json["scenes"][0]["extras"]["rt"]["background_gradient"]["horizon"], Json::array({0.0f, 0.0f, 0.5f}));
    const Scene back = load_scene_from_memory(std::as_bytes(std::span(glb.data(), glb.size())), "model.glb");
    EXPECT_EQ(back.background, lit.background);
}

}  // namespace
}  // namespace rt
