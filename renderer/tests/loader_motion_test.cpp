// Where moving scenes come from: rt.NodeMotion in the sidecar or glTF
// `extras.rt` (glTF nodes by name, OBJ objects and groups by name), and a
// glTF's first animation; and the errors hostile ones get.
#include <cmath>

#include <gtest/gtest.h>

#include "loader_test_util.h"

namespace rt {
namespace {

using namespace rt::testing;

void expect_near(vec3 actual, vec3 expected) {
    EXPECT_NEAR(actual.x, expected.x, 1e-5f);
    EXPECT_NEAR(actual.y, expected.y, 1e-5f);
    EXPECT_NEAR(actual.z, expected.z, 1e-5f);
}

const std::vector<float> kTriangle = {0, 0, 0, 1, 0, 0, 0, 1, 0};

// One triangle at the origin under a node named "mover" (its index returned),
// with `fields` added to that node.
int add_mover(GltfDoc& doc, const Json& fields = Json::object()) {
    Json node = fields;
    node["name"] = "mover";
    return doc.add_mesh_node({{"attributes", {{"POSITION", doc.add_vec3(kTriangle)}}}}, node);
}

// The first animation, with one channel per (node, path, sampler).
void animate(GltfDoc& doc, int node, const std::string& path, int input, int output,
             const std::string& interpolation = "LINEAR") {
    Json& animations = doc.json["animations"];
    if (animations.is_null()) animations = Json::array({{{"channels", Json::array()}, {"samplers", Json::array()}}});
    Json& animation = animations[0];
    animation["samplers"].push_back({{"input", input}, {"output", output}, {"interpolation", interpolation}});
    animation["channels"].push_back(
        {{"sampler", animation["samplers"].size() - 1}, {"target", {{"node", node}, {"path", path}}}});
}

int add_times(GltfDoc& doc, const std::vector<float>& times) { return doc.add_accessor(times, 5126, "SCALAR", 1); }

TEST(LoaderMotion, ObjObjectsMoveInWorldSpaceAndTheRestStandsStill) {
    TempDir dir;
    // A quarter turn about +Y, then 2 along +X.
    dir.write("s.rt.json", R"({"motions": [{"node": "mover", "translation": [2, 0, 0],
                                            "rotation": [0, 0.7071068, 0, 0.7071068]}]})");
    const Scene scene = load_scene(dir.write("s.obj", "o still\nv 0 0 5\nv 1 0 5\nv 0 1 5\nf 1 2 3\no mover\n"
                                                      "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 4//1 5//1 6//1\n"));
    ASSERT_TRUE(scene.moving());
    ASSERT_EQ(scene.positions_close.size(), 6u);
    for (uint32_t v = 0; v < 3; ++v) EXPECT_EQ(scene.positions_close[v], scene.positions[v]);
    expect_near(scene.positions_close[4], {2, 0, -1});  // (1, 0, 0) turned to (0, 0, -1)
    expect_near(scene.positions_close[5], {2, 1, 0});
    expect_near(scene.normals_close[3], {1, 0, 0});
    expect_near(scene.normals[3], {0, 0, 1});
    // The bounds hold the scene over the whole shutter interval.
    EXPECT_EQ(scene.bounds().max.x, 2.0f);
}

TEST(LoaderMotion, ObjMotionsNameObjectsThatExistAndRotateByQuaternions) {
    TempDir dir;
    const std::string obj = "g body\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    dir.write("s.rt.json", R"({"motions": [{"node": "wheel", "translation": [1, 0, 0]}]})");
    EXPECT_EQ(scene_error([&] { load_scene(dir.write("s.obj", obj)); }),
              "s.rt.json: extras.motions[0]: the scene s.obj has no object or group 'wheel'");
    dir.write("s.rt.json", R"({"motions": [{"node": "body", "rotation": [0, 0, 0, 0]}]})");
    EXPECT_EQ(scene_error([&] { load_scene(dir.write("s.obj", obj)); }),
              "s.rt.json: extras.motions[0].rotation: is not a rotation (a zero quaternion)");
    dir.write("s.rt.json", R"({"motions": [{"translation": [1, 0, 0]}]})");
    EXPECT_EQ(scene_error([&] { load_scene(dir.write("s.obj", obj)); }),
              "s.rt.json: extras.motions[0].node: names no node");
    dir.write("s.rt.json", R"({"motions": [{"node": "body", "scale": [1, 2]}]})");
    EXPECT_EQ(scene_error([&] { load_scene(dir.write("s.obj", obj)); }),
              "s.rt.json: extras.motions[0].scale: needs 3 values, got 2");
    dir.write("s.rt.json", R"({"motions": [{"node": "body", "scale": [2, 2, 2]}, {"node": "body"}]})");
    EXPECT_EQ(scene_error([&] { load_scene(dir.write("s.obj", obj)); }),
              "s.rt.json: extras.motions[1]: object or group 'body' has a motion already");
    dir.write("s.rt.json", R"({"motions": [{"node": "body", "translation": [3e38, 0, 0], "scale": [1e38, 1, 1]}]})");
    EXPECT_EQ(scene_error([&] { load_scene(dir.write("s.obj", obj)); }),
              "s.rt.json: extras.motions[0]: moves v #2 out of range");
}

TEST(LoaderMotion, GltfMotionsReplaceTheNodesTransformAndCarryItsChildren) {
    GltfDoc doc;
    const int child = add_mover(doc, {{"translation", {0, 1, 0}}});
    doc.json["scenes"][0]["nodes"] = Json::array();
    doc.add_root({{"name", "arm"}, {"translation", {5, 0, 0}}, {"scale", {2, 2, 2}}, {"children", {child}}});
    doc.json["asset"]["extras"]["rt"] = {{"motions", {{{"node", "arm"}, {"translation", {0, 0, 3}}}}}};
    const Scene scene = load_text(doc.text(), "a.gltf");
    ASSERT_TRUE(scene.moving());
    // Open: the rest pose. Close: the arm's scale stays (the motion leaves it out), its translation is the motion's.
    expect_near(scene.positions[1], {7, 2, 0});
    expect_near(scene.positions_close[1], {2, 2, 3});
}

TEST(LoaderMotion, GltfMotionsNeedOneNodeOfTheirName) {
    GltfDoc doc;
    add_mover(doc);
    doc.json["asset"]["extras"]["rt"] = {{"motions", {{{"node", "nobody"}, {"translation", {1, 0, 0}}}}}};
    EXPECT_EQ(scene_error([&] { load_text(doc.text(), "a.gltf"); }),
              "a.gltf: asset.extras.rt.motions[0]: the scene a.gltf has no node 'nobody'");
    doc.json["asset"]["extras"]["rt"] = {{"motions", {{{"node", "mover"}, {"translation", {1, 0, 0}}}}}};
    doc.add_root({{"name", "mover"}});
    EXPECT_EQ(scene_error([&] { load_text(doc.text(), "a.gltf"); }),
              "a.gltf: asset.extras.rt.motions[0]: 2 nodes of a.gltf are named 'mover': a motion needs a name only "
              "one node has");

    GltfDoc matrix;
    add_mover(matrix, {{"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}}});
    matrix.json["asset"]["extras"]["rt"] = {{"motions", {{{"node", "mover"}, {"translation", {1, 0, 0}}}}}};
    EXPECT_EQ(scene_error([&] { load_text(matrix.text(), "a.gltf"); }),
              "a.gltf: asset.extras.rt.motions[0]: node 'mover' is placed by a matrix: its motion must give "
              "translation, rotation and scale");
    matrix.json["asset"]["extras"]["rt"]["motions"][0]["rotation"] = {0, 0, 0, 1};
    matrix.json["asset"]["extras"]["rt"]["motions"][0]["scale"] = {1, 1, 1};
    expect_near(load_text(matrix.text(), "a.gltf").positions_close[0], {1, 0, 0});
}

// The shutter opens at the first keyframe and closes at the last, whatever the
// interpolation; what happens in between is not followed.
TEST(LoaderMotion, GltfAnimationsMoveNodesFromTheirFirstToTheirLastKeyframe) {
    GltfDoc doc;
    const int node = add_mover(doc, {{"translation", {9, 9, 9}}});
    animate(doc, node, "translation", add_times(doc, {0, 1, 2}), doc.add_vec3({0, 0, 0, 5, 5, 5, 1, 0, 0}));
    // Rotation by a cubic spline: in-tangent, value, out-tangent per keyframe; a quarter turn about +Z at the end.
    const float s = 0.7071068f;
    animate(doc, node, "rotation", add_times(doc, {0.5f, 3}),
            doc.add_accessor(std::vector<float>{7, 7, 7, 7, 0, 0, 0, 1, 7, 7, 7, 7, 7, 7, 7, 7, 0, 0, s, s, 7, 7, 7, 7},
                             5126, "VEC4", 4),
            "CUBICSPLINE");
    animate(doc, node, "scale", add_times(doc, {1}), doc.add_vec3({2, 2, 2}), "STEP");
    const Scene scene = load_text(doc.text(), "a.gltf");
    ASSERT_TRUE(scene.moving());
    expect_near(scene.positions[1], {2, 0, 0});        // the rest translation is not the pose at open
    expect_near(scene.positions_close[1], {1, 2, 0});  // (2, 0, 0) turned to (0, 2, 0), then moved
}

TEST(LoaderMotion, MotionsWinOverTheAnimationAtShutterClose) {
    GltfDoc doc;
    const int node = add_mover(doc);
    animate(doc, node, "translation", add_times(doc, {0, 1}), doc.add_vec3({1, 0, 0, 2, 0, 0}));
    doc.json["asset"]["extras"]["rt"] = {{"motions", {{{"node", "mover"}, {"scale", {3, 3, 3}}}}}};
    const Scene scene = load_text(doc.text(), "a.gltf");
    expect_near(scene.positions[1], {2, 0, 0});
    expect_near(scene.positions_close[1], {3, 0, 0});  // the rest translation (none), the motion's scale
}

TEST(LoaderMotion, AnimatedCamerasGetAPoseAtShutterClose) {
    GltfDoc doc;
    add_mover(doc);
    doc.json["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.1}}}}};
    const int camera = doc.add_root({{"camera", 0}, {"translation", {0, 0, 5}}});
    animate(doc, camera, "translation", add_times(doc, {0, 1}), doc.add_vec3({0, 0, 5, 1, 0, 5}));
    const Scene scene = load_text(doc.text(), "a.gltf");
    ASSERT_EQ(scene.cameras.size(), 1u);
    const Camera& c = scene.cameras[0].camera;
    ASSERT_TRUE(c.has_shutter_close());
    EXPECT_FLOAT_EQ(c.shutter_close().position(0), 1.0f);
    EXPECT_FLOAT_EQ(c.shutter_close().target(2), 4.0f);
    EXPECT_FALSE(scene.moving());  // the camera moves, the mesh does not
}

TEST(LoaderMotion, HostileAnimationsAreRefusedByName) {
    const auto error = [](const std::function<void(GltfDoc&, int)>& spoil) {
        GltfDoc doc;
        const int node = add_mover(doc);
        const int times = add_times(doc, {0, 1});  // accessors[1]
        animate(doc, node, "translation", times, doc.add_vec3({0, 0, 0, 1, 0, 0}));  // accessors[2]
        spoil(doc, node);
        return scene_error([&] { load_text(doc.text(), "a.gltf"); });
    };
    EXPECT_EQ(error([&](GltfDoc& d, int) { d.json["animations"][0]["channels"][0]["target"]["node"] = 7; }),
              "a.gltf: animations[0].channels[0].target.node refers to node 7, which does not exist");
    EXPECT_EQ(error([&](GltfDoc& d, int) { d.json["animations"][0]["channels"][0]["sampler"] = 3; }),
              "a.gltf: animations[0].channels[0].sampler refers to sampler 3, which does not exist");
    EXPECT_EQ(error([&](GltfDoc& d, int) { d.json["animations"][0]["samplers"][0]["input"] = add_times(d, {1, 1}); }),
              "a.gltf: animations[0].samplers[0] input (accessors[3]) keyframe times do not increase at element 1");
    EXPECT_EQ(error([&](GltfDoc& d, int) { d.json["animations"][0]["samplers"][0]["input"] = add_times(d, {0, NAN}); }),
              "a.gltf: animations[0].samplers[0] input (accessors[3]) keyframe time 1 is not finite");
    EXPECT_EQ(error([&](GltfDoc& d, int) { d.json["animations"][0]["samplers"][0]["output"] = d.add_vec3({0, 0, 0}); }),
              "a.gltf: animations[0].samplers[0] output (accessors[3]) has 1 elements for 2 keyframes, expected 2");
    EXPECT_EQ(error([&](GltfDoc& d, int) { d.json["animations"][0]["samplers"][0]["interpolation"] = "CUBICSPLINE"; }),
              "a.gltf: animations[0].samplers[0] output (accessors[2]) has 2 elements for 2 keyframes, expected 6");
    EXPECT_EQ(error([&](GltfDoc& d, int) { d.json["animations"][0]["samplers"][0]["interpolation"] = "BEZIER"; }),
              "a.gltf: animations[0].samplers[0] has unknown interpolation 'BEZIER'");
    EXPECT_EQ(error([&](GltfDoc& d, int) {
                  d.json["animations"][0]["samplers"][0]["output"] = d.add_vec3({0, 0, 0, NAN, 0, 0});
              }),
              "a.gltf: animations[0].samplers[0] output (accessors[3]) element 1 is not finite");
    EXPECT_EQ(error([&](GltfDoc& d, int) { d.json["accessors"][2]["count"] = 1000; }),
              "a.gltf: animations[0].samplers[0] output (accessors[2]) has 1000 elements from byteOffset 0, which "
              "reach past the end of bufferViews[2] (24 bytes)");
    EXPECT_EQ(error([&](GltfDoc& d, int node) { animate(d, node, "rotation", 1, 2); }),
              "a.gltf: animations[0].samplers[1] output (accessors[2]) has type VEC3, expected VEC4");
    EXPECT_EQ(error([&](GltfDoc& d, int node) {
                  animate(d, node, "rotation", 1, d.add_accessor(std::vector<float>(8, 0.0f), 5126, "VEC4", 4));
              }),
              "a.gltf: animations[0].channels[1] turns nodes[0] by a zero quaternion");
    EXPECT_EQ(error([&](GltfDoc& d, int node) { animate(d, node, "translation", 1, 2); }),
              "a.gltf: animations[0].channels[1] animates nodes[0].translation a second time");
    EXPECT_EQ(error([&](GltfDoc& d, int) {
                  d.json["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
              }),
              "a.gltf: animations[0].channels[0] animates nodes[0], which is placed by a matrix: only translation, "
              "rotation and scale can be animated");

    // Morph target weights are not followed: a warning, and nothing moves.
    GltfDoc doc;
    const int node = add_mover(doc);
    const int times = add_times(doc, {0, 1});
    animate(doc, node, "weights", times, doc.add_accessor(std::vector<float>{0, 1}, 5126, "SCALAR", 1));
    const Scene scene = load_text(doc.text(), "a.gltf");
    EXPECT_FALSE(scene.moving());
    EXPECT_TRUE(has_warning(scene, "animations[0].channels[0] animates 'weights', which is not supported: ignored"));
}

}  // namespace
}  // namespace rt
