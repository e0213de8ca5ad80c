// Orthographic cameras through the loaders: glTF `orthographic` cameras read
// (ymag as half the height) and their bad values refused by field, the
// sidecar's, and model.glb's round trip.
#include <cmath>

#include <gtest/gtest.h>

#include "export/glb_export.h"
#include "loader_test_util.h"

namespace rt {
namespace {

using namespace rt::testing;

// A triangle, and a camera node 5 units up +z looking down -z at it.
GltfDoc camera_doc(const Json& camera) {
    GltfDoc doc;
    Json primitive = {{"attributes", {{"POSITION", doc.add_vec3({0, 0, 0, 1, 0, 0, 0, 1, 0})}}}};
    doc.add_mesh_node(primitive);
    doc.json["cameras"] = {camera};
    doc.add_root({{"camera", 0}, {"translation", {0, 0, 5}}});
    return doc;
}

Json ortho(double xmag, double ymag, double znear = 0.0, double zfar = 100.0) {
    return {{"type", "orthographic"}, {"name", "plan"},
            {"orthographic", {{"xmag", xmag}, {"ymag", ymag}, {"znear", znear}, {"zfar", zfar}}}};
}

TEST(LoaderCamera, GltfOrthographicCameraKeepsYmagAsHalfItsHeight) {
    const Scene scene = load_text(camera_doc(ortho(3.0, 1.5)).text(), "o.gltf");
    ASSERT_EQ(scene.cameras.size(), 1u);
    const SceneCamera& named = scene.cameras[0];
    EXPECT_EQ(named.name, "plan");
    EXPECT_EQ(named.camera.projection(), ORTHOGRAPHIC);
    EXPECT_FLOAT_EQ(named.camera.ortho_height(), 3.0f);
    EXPECT_FLOAT_EQ(named.camera.position(2), 5.0f);
    EXPECT_FLOAT_EQ(named.camera.target(2), 4.0f);
    for (const std::string& warning : scene.warnings) EXPECT_FALSE(contains(warning, "skipped")) << warning;
    // A perspective camera stays one.
    const Scene perspective = load_text(
        camera_doc({{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}}).text(), "p.gltf");
    ASSERT_EQ(perspective.cameras.size(), 1u);
    EXPECT_EQ(perspective.cameras[0].camera.projection(), PERSPECTIVE);
    EXPECT_FALSE(perspective.cameras[0].camera.has_ortho_height());
}

TEST(LoaderCamera, BadOrthographicValuesAreRefusedByField) {
    const auto error = [](const Json& camera) {
        return scene_error([&] { load_text(camera_doc(camera).text(), "o.gltf"); });
    };
    EXPECT_EQ(error(ortho(1.0, 0.0)), "o.gltf: cameras[0].orthographic.ymag: 0 must be above 0");
    EXPECT_EQ(error(ortho(1.0, -2.0)), "o.gltf: cameras[0].orthographic.ymag: -2 must be above 0");
    EXPECT_EQ(error(ortho(0.0, 1.0)), "o.gltf: cameras[0].orthographic.xmag: 0 must be above 0");
    EXPECT_EQ(error(ortho(1.0, 1.0, -1.0)), "o.gltf: cameras[0].orthographic.znear: -1 must not be negative");
    EXPECT_EQ(error(ortho(1.0, 1.0, 2.0, 1.0)), "o.gltf: cameras[0].orthographic.zfar: 1 must be above znear");
    EXPECT_EQ(error(ortho(1.0, 1e300)), "o.gltf: cameras[0].ortho_height: must be a finite number");
}

TEST(LoaderCamera, SidecarOrthographicCameraNeedsItsHeight) {
    TempDir dir;
    const auto scene = dir.write("s.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const std::string pose = R"("position": [0, 0, 5], "target": [0, 0, 0])";
    dir.write("s.rt.json", R"({"cameras": [{"name": "top", "camera": {)" + pose +
                               R"(, "projection": "ORTHOGRAPHIC", "orthoHeight": 2.5}}]})");
    const Scene loaded = load_scene(scene);
    ASSERT_EQ(loaded.cameras.size(), 1u);
    EXPECT_EQ(loaded.cameras[0].camera.projection(), ORTHOGRAPHIC);
    EXPECT_FLOAT_EQ(loaded.cameras[0].camera.ortho_height(), 2.5f);

    dir.write("s.rt.json", R"({"cameras": [{"camera": {)" + pose + R"(, "projection": "ORTHOGRAPHIC"}}]})");
    EXPECT_EQ(scene_error([&] { load_scene(scene); }),
              "s.rt.json: extras.cameras[0].camera.ortho_height: is required for an ORTHOGRAPHIC camera");
    dir.write("s.rt.json", R"({"cameras": [{"camera": {)" + pose +
                               R"(, "projection": "ORTHOGRAPHIC", "orthoHeight": -1}}]})");
    EXPECT_EQ(scene_error([&] { load_scene(scene); }),
              "s.rt.json: extras.cameras[0].camera.ortho_height: -1 is below the minimum 1e-30");
}

TEST(LoaderCamera, OrthographicCameraSurvivesModelGlb) {
    const Scene scene = load_text(camera_doc(ortho(3.0, 1.5)).text(), "o.gltf");
    const std::string glb = export_glb(scene);
    const Scene back = load_scene_from_memory(std::as_bytes(std::span(glb.data(), glb.size())), "model.glb");
    ASSERT_EQ(back.cameras.size(), 1u);
    EXPECT_EQ(back.cameras[0].camera.projection(), ORTHOGRAPHIC);
    EXPECT_FLOAT_EQ(back.cameras[0].camera.ortho_height(), 3.0f);
    EXPECT_NEAR(back.cameras[0].camera.position(2), 5.0f, 1e-5f);
}

}  // namespace
}  // namespace rt
