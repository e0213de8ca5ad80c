// What both loaders share: dispatch by extension, and the finalisation (dropped
// degenerate triangles, completed normals, default material, warnings, bounds).
#include <limits>

#include <gtest/gtest.h>

#include "loader_test_util.h"

namespace rt {
namespace {

using namespace rt::testing;

TEST(LoaderFinalise, DegenerateTrianglesAreDroppedAndCounted) {
    // A good triangle, one with a repeated vertex, one collinear.
    const Scene scene = load_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\n"
                                  "f 1 2 3\nf 1 2 2\nf 1 2 4\n",
                                  "d.obj");
    EXPECT_EQ(scene.triangles.size(), 1u);
    EXPECT_EQ(scene.triangle_materials.size(), 1u);
    EXPECT_EQ(scene.degenerate_triangles, 2u);
    EXPECT_TRUE(has_warning(scene, "dropped 2 degenerate triangles"));
    // Vertex 4 is used by a dropped triangle only, and goes with it.
    EXPECT_EQ(scene.positions.size(), 3u);
    EXPECT_EQ(scene.normals.size(), 3u);
}

// Twice the area is formed in double (triangle.h), so only triangles with no
// area at all go: not tiny ones, whose area underflows a float, nor large
// ones, whose area overflows it though rays hit them.
TEST(LoaderFinalise, OnlyTrianglesWithoutAreaAreDegenerate) {
    const Scene scene = load_text("v 0 0 0\nv 1e-20 0 0\nv 0 1e-20 0\n"
                                  "v 0 0 1\nv 1e10 0 1\nv 0 1e10 1\n"
                                  "v 0 0 2\nv 3e38 0 2\nv 0 3e38 2\n"
                                  "v 0 0 3\nv 1 1 3\nv 2 2 3\n"
                                  "f 1 2 3\nf 4 5 6\nf 7 8 9\nf 10 11 12\n",
                                  "sizes.obj");
    EXPECT_EQ(scene.triangles.size(), 3u);
    EXPECT_EQ(scene.degenerate_triangles, 1u);
}

TEST(LoaderFinalise, ZeroNormalsBecomeTheFaceNormalAndOthersAreNormalised) {
    GltfDoc doc;
    const int positions = doc.add_vec3({0, 0, 0, 1, 0, 0, 0, 1, 0});
    const int normals = doc.add_vec3({0, 0, 0, 0, 0, 5, 0, 3, 4});
    doc.add_mesh_node({{"attributes", {{"POSITION", positions}, {"NORMAL", normals}}}});
    const Scene scene = load_text(doc.text(), "z.gltf");
    ASSERT_EQ(scene.triangles.size(), 1u);
    const uvec3 t = scene.triangles[0];
    EXPECT_EQ(scene.normals[t.x], vec3(0, 0, 1));
    EXPECT_EQ(scene.normals[t.y], vec3(0, 0, 1));
    EXPECT_NEAR(scene.normals[t.z].y, 0.6f, 1e-6f);
    EXPECT_NEAR(scene.normals[t.z].z, 0.8f, 1e-6f);
}

TEST(LoaderFinalise, EveryTriangleGetsAValidMaterial) {
    const Scene scene = load_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "m.obj");
    ASSERT_EQ(scene.materials.size(), 1u);
    EXPECT_EQ(scene.materials[0].name, "default");
    EXPECT_EQ(scene.triangle_materials[0], 0u);
    EXPECT_EQ(scene.materials[0].diffuse, vec3(0.8f));
}

TEST(LoaderFinalise, SceneWithoutLightsIsWarnedAbout) {
    const Scene scene = load_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "m.obj");
    EXPECT_TRUE(has_warning(scene, "m.obj: scene has no lights: "));
    EXPECT_TRUE(scene.texcoords.empty());
}

TEST(LoaderFinalise, BoundsCoverTrianglesAndSpheres) {
    TempDir dir;
    dir.write("b.rt.json", R"({"spheres": [{"center": [5, 0, 0], "radius": 2}]})");
    const Scene scene = load_scene(dir.write("b.obj", "v 0 0 0\nv 1 0 -1\nv 0 1 0\nf 1 2 3\n"));
    const Bounds3 bounds = scene.bounds();
    EXPECT_EQ(bounds.min, vec3(0, -2, -2));
    EXPECT_EQ(bounds.max, vec3(7, 2, 2));
    EXPECT_TRUE(Scene().bounds().empty());
}

TEST(LoaderDispatch, FormatComesFromTheExtensionWhateverItsCase) {
    EXPECT_EQ(load_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "UPPER.OBJ").triangles.size(), 1u);
    EXPECT_EQ(scene_error([] { load_text("solid x\n", "model.stl"); }),
              "model.stl: unknown scene format '.stl' (expected .gltf, .glb or .obj)");
}

TEST(LoaderDispatch, MissingSceneFileIsAnError) {
    TempDir dir;
    EXPECT_EQ(scene_error([&] { load_scene(dir.path() / "nothing.gltf"); }), "nothing.gltf: file not found");
}

TEST(LoaderDispatch, WarningsNameTheSceneFile) {
    const Scene scene = load_scene(RT_TEST_DATA_DIR "/triangle.gltf");
    ASSERT_EQ(scene.triangles.size(), 1u);
    EXPECT_EQ(scene.materials[scene.triangle_materials[0]].name, "red");
    EXPECT_EQ(scene.positions[scene.triangles[0].y], vec3(1, 0, -1));
    for (const std::string& warning : scene.warnings) EXPECT_EQ(warning.rfind("triangle.gltf: ", 0), 0u) << warning;
}

}  // namespace
}  // namespace rt
