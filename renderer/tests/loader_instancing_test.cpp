// glTF nodes that share a mesh: one stored copy and an instance per node
// (moving ones too), rays meeting the same surfaces as the file with a copy
// per node at every time, the copies kept where a node flattens the mesh
// (also for a moment of its motion), degenerate triangles dropped inside
// shared meshes, and model.glb keeping the sharing.
#include <cstring>

#include <gtest/gtest.h>

#include "export/glb_export.h"
#include "geometry/accel.h"
#include "loader_test_util.h"
#include "test_meshes.h"

namespace rt {
namespace {

using namespace rt::testing;

// An octahedron, 8 triangles, with one degenerate triangle after them.
Json octahedron(GltfDoc& doc) {
    const std::vector<float> p = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
    const std::vector<uint32_t> i = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5, 0, 0, 1};
    return {{"attributes", {{"POSITION", doc.add_vec3(p)}}}, {"indices", doc.add_indices(i)}};
}

Json placed(int mesh, int k) {
    const float a = 0.4f * float(k);
    return {{"mesh", mesh},
            {"translation", {3.0f * float(k), 0.5f * float(k % 2), -1.0f}},
            {"rotation", {0.0f, std::sin(a / 2), 0.0f, std::cos(a / 2)}},
            {"scale", {1.0f + 0.2f * float(k), k == 3 ? -0.7f : 0.7f, 1.0f}}};
}

// `nodes` nodes drawing one mesh, or (copies) each its own copy of it.
GltfDoc shared_doc(int nodes, bool copies) {
    GltfDoc doc;
    for (int k = 0; k < nodes; ++k) {
        if (k == 0 || copies) doc.json["meshes"].push_back({{"primitives", Json::array({octahedron(doc)})}});
        doc.add_root(placed(int(doc.json["meshes"].size()) - 1, k));
    }
    return doc;
}

TEST(LoaderInstancing, NodesSharingAMeshStoreItOnceAndMeetTheSameSurfaces) {
    const Scene shared = load_bytes(shared_doc(6, false).glb(), "shared.glb");
    const Scene copies = load_bytes(shared_doc(6, true).glb(), "copies.glb");
    ASSERT_EQ(shared.meshes.size(), 1u);
    EXPECT_EQ(shared.instances.size(), 6u);
    EXPECT_EQ(shared.triangles.size(), 8u) << "one copy, its degenerate triangle dropped";
    EXPECT_EQ(shared.meshes[0].triangle_count, 8u);
    EXPECT_TRUE(copies.instances.empty());
    EXPECT_EQ(copies.triangles.size(), 48u);
    EXPECT_EQ(shared.degenerate_triangles, 1u);
    ASSERT_EQ(shared.instance_names.size(), 6u);
    EXPECT_EQ(shared.instance_names[4], "nodes[4]");
    const Accelerator a(shared), b(copies);
    size_t hits = 0;
    for (const Ray& ray : random_rays(copies, 3000, 5)) {
        Hit ha, hb;
        const bool found = a.intersect(ray, ha);
        ASSERT_EQ(found, b.intersect(ray, hb));
        if (!found) continue;
        ++hits;
        EXPECT_NEAR(ha.t, hb.t, 1e-4f * hb.t);
        EXPECT_NE(ha.instance, kNoInstance);
    }
    EXPECT_GT(hits, 1000u);
}

TEST(LoaderInstancing, AFlatteningNodeKeepsItsOwnCopy) {
    GltfDoc doc = shared_doc(3, false);
    doc.json["nodes"][1]["scale"] = {1.0f, 0.0f, 1.0f};  // flattened: no inverse
    const Scene scene = load_bytes(doc.glb(), "flat.glb");
    EXPECT_EQ(scene.instances.size(), 2u);
    EXPECT_EQ(scene.meshes.size(), 1u);
    EXPECT_EQ(scene.world_triangles(), 8u) << "the flattened copy, in world space";

    GltfDoc once = shared_doc(2, false);
    once.json["nodes"][1]["scale"] = {1.0f, 0.0f, 1.0f};
    const Scene single = load_bytes(once.glb(), "once.glb");
    EXPECT_TRUE(single.meshes.empty()) << "a mesh placed once after all is copied like any";
    EXPECT_EQ(single.triangles.size(), 16u);
}

// Nodes 1 and 2 move (a sidecar motion each); with copies, the same motions.
Scene moving_scene(const TempDir& dir, bool copies, const std::string& node2_close) {
    GltfDoc doc = shared_doc(4, copies);
    // std::string("n") +, not "n" +: GCC 12 warns wrongly of overlapping copies in the latter (its bug 105329).
    for (int k = 0; k < 4; ++k) doc.json["nodes"][k]["name"] = std::string("n") + std::to_string(k);
    dir.write("s.rt.json", R"({"motions": [{"node": "n1", "translation": [3, 1, -1], "rotation": [0, 0.3, 0, 0.9539392]},
                                          {"node": "n2", )" + node2_close + "}]}");
    const Bytes glb = doc.glb();
    return load_scene(dir.write("s.glb", glb));
}

TEST(LoaderInstancing, MovingNodesAreMovingInstancesThatMeetWhatTheCopiesMeet) {
    TempDir a, b;
    const std::string slide = R"("translation": [6, 0.5, -2])";
    const Scene shared = moving_scene(a, false, slide), copies = moving_scene(b, true, slide);
    ASSERT_EQ(shared.instances.size(), 4u);
    EXPECT_TRUE(shared.moving() && copies.moving());
    EXPECT_FALSE(shared.instances[0].moving);
    EXPECT_TRUE(shared.instances[1].moving && shared.instances[2].moving);
    EXPECT_EQ(shared.instance_names[2], "n2");
    const Accelerator accel(shared), flat(copies);
    std::vector<Ray> rays = random_rays(copies, 4000, 9);
    size_t hits = 0, moving_hits = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        Ray& ray = rays[i];
        ray.time = float(i % 11) / 10.0f;
        Hit ha, hb;
        const bool found = accel.intersect(ray, ha);
        ASSERT_EQ(found, flat.intersect(ray, hb)) << "ray " << i << " at time " << ray.time;
        if (!found) continue;
        ++hits;
        moving_hits += shared.instances[ha.instance].moving;
        EXPECT_NEAR(ha.t, hb.t, 1e-4f * hb.t);
    }
    EXPECT_GT(moving_hits, 300u) << "of " << hits;
}

TEST(LoaderInstancing, AMotionThatFlattensTheMeshOnTheWayKeepsItsOwnCopy) {
    TempDir dir;
    // Node 2's scale goes from 0.7 to -0.7 in y: flat halfway, so no inverse then.
    const Scene scene = moving_scene(dir, false, R"("translation": [6, 0.5, -1], "scale": [1.4, -0.7, 1])");
    EXPECT_EQ(scene.instances.size(), 3u);
    EXPECT_EQ(scene.world_triangles(), 8u) << "node 2's copy, moving in world space";
    // A half turn more than at open, blended straight, flattens too (the blend of R(a) and R(a + 180°) is singular at 0.5).
    TempDir turn;
    const Scene half = moving_scene(turn, false, R"("translation": [6, 0.5, -1], "rotation": [0, 0.9210610, 0, -0.3894183])");
    EXPECT_EQ(half.instances.size(), 3u);
}

TEST(LoaderInstancing, ModelGlbKeepsTheSharing) {
    const Scene shared = load_bytes(shared_doc(40, false).glb(), "shared.glb");
    const Scene copies = load_bytes(shared_doc(40, true).glb(), "copies.glb");
    const std::string glb = export_glb(shared);
    const std::string flat_glb = export_glb(copies);
    // One mesh drawn by 40 nodes, its vertices written once.
    uint32_t json_length;
    std::memcpy(&json_length, glb.data() + 12, 4);
    const Json doc = Json::parse(glb.substr(20, json_length));
    ASSERT_EQ(doc["meshes"].size(), 1u);
    size_t drawing = 0;
    for (const Json& node : doc["nodes"]) drawing += node.contains("mesh") && node.contains("matrix");
    EXPECT_EQ(drawing, 40u);
    EXPECT_LT(glb.size(), flat_glb.size());
    const Scene again = load_bytes(Bytes(glb.begin(), glb.end()), "model.glb");
    EXPECT_EQ(again.meshes.size(), 1u);
    EXPECT_EQ(again.instances.size(), 40u);
    EXPECT_EQ(again.triangles.size(), shared.triangles.size());
    const Bounds3 a = again.bounds(), b = shared.bounds();
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(a.min[k], b.min[k], 1e-4f);
        EXPECT_NEAR(a.max[k], b.max[k], 1e-4f);
    }
}

}  // namespace
}  // namespace rt
