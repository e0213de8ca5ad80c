// The accelerator over a scene: level export for the debugger, rays through the
// shared edges and vertices of closed meshes, debug queries, empty scenes.
#include "geometry/accel.h"

#include <gtest/gtest.h>

#include "test_meshes.h"

namespace rt {
namespace {

using namespace rt::testing;

TEST(Accel, LevelBoxesCoverAllTriangles) {
    const Scene scene = icosphere(4);
    const Accelerator accel(scene);
    const uint32_t depth = accel.stats().depth;
    ASSERT_GT(depth, 2u);
    EXPECT_EQ(accel.boxes(0).nodes.size(), 1u);
    EXPECT_LE(accel.boxes(1).nodes.size(), size_t(bvh::kWideWidth));
    // A level's boxes, with the leaves above it, hold every triangle once.
    size_t in_leaves_above = 0;
    for (int level = 0; level <= int(depth); ++level) {
        const Accelerator::LevelBoxes boxes = accel.boxes(level);
        ASSERT_FALSE(boxes.nodes.empty()) << "level " << level;
        size_t triangles = in_leaves_above;
        for (size_t i = 0; i < boxes.nodes.size(); ++i) {
            triangles += boxes.triangles[i];
            if (boxes.leaf[i]) in_leaves_above += boxes.triangles[i];
        }
        EXPECT_EQ(triangles, scene.triangles.size()) << "level " << level;
    }
    EXPECT_EQ(in_leaves_above, scene.triangles.size());
    const Accelerator::LevelBoxes leaves = accel.boxes(-1);
    EXPECT_EQ(leaves.nodes.size(), accel.stats().leaves);
    size_t triangles = 0;
    for (size_t i = 0; i < leaves.nodes.size(); ++i) {
        triangles += leaves.triangles[i];
        EXPECT_GE(leaves.nodes[i], accel.stats().nodes) << "leaves are numbered after the nodes";
        EXPECT_TRUE(leaves.leaf[i]);
    }
    EXPECT_EQ(triangles, scene.triangles.size());
    EXPECT_TRUE(accel.boxes(int(depth) + 1).nodes.empty());
}

// Every ray from inside a closed mesh must hit it, also through its edges and
// vertices, where a leak would show.
void expect_no_leaks(const Scene& scene, vec3 inside, std::span<const vec3> targets) {
    const Accelerator accel(scene);
    int leaks = 0;
    for (const vec3& target : targets) {
        for (const Ray& ray : {Ray{inside, target - inside, kInfinity}, Ray{2.0f * target - inside, inside - target, kInfinity}}) {
            Hit hit;
            if (!accel.intersect(ray, hit) || !accel.occluded(ray)) ++leaks;
        }
    }
    EXPECT_EQ(leaks, 0) << "of " << 2 * targets.size() << " rays";
}

TEST(Accel, RaysThroughEdgesAndVerticesOfIcosphereDoNotLeak) {
    const Scene scene = icosphere(3);
    std::vector<vec3> targets = scene.positions;
    for (const uvec3& t : scene.triangles)
        for (int k = 0; k < 3; ++k)
            for (float s : {0.5f, 0.25f, 1.0f / 3.0f}) targets.push_back(glm::mix(scene.positions[t[k]], scene.positions[t[(k + 1) % 3]], s));
    for (vec3 inside : {vec3(0.0f), vec3(0.1f, -0.2f, 0.3f)}) expect_no_leaks(scene, inside, targets);
}

TEST(Accel, AxisAlignedRaysThroughCubeEdgesDoNotLeak) {
    // Rays along -z through the top face's corners, edges and diagonal, where
    // the ray lies in the planes of side faces and of the triangles' flat boxes.
    const Scene scene = cube();
    std::vector<vec3> targets;
    for (float x : {-1.0f, -0.5f, 0.0f, 0.25f, 1.0f})
        for (float y : {-1.0f, -0.5f, 0.0f, 0.25f, 1.0f}) targets.emplace_back(x, y, 1.0f);
    for (float s : {-1.0f, -0.3f, 0.0f, 0.7f, 1.0f}) targets.emplace_back(s, s, 1.0f);
    const Accelerator accel(scene);
    for (const vec3& target : targets) {
        Hit hit;
        const Ray ray{target + vec3(0, 0, 4), vec3(0, 0, -1), kInfinity};
        EXPECT_TRUE(accel.intersect(ray, hit)) << "through " << target.x << ", " << target.y;
        EXPECT_NEAR(hit.t, 4.0f, 1e-6f);
        EXPECT_TRUE(accel.occluded(ray));
    }
    expect_no_leaks(scene, vec3(0.0f), targets);
}

TEST(Accel, RaysThroughGridVerticesAndEdgesHit) {
    const Scene scene = grid(8);
    const Accelerator accel(scene);
    for (float x = 0.0f; x <= 8.0f; x += 0.5f) {
        for (float y = 0.0f; y <= 8.0f; y += 0.5f) {
            Hit hit;
            EXPECT_TRUE(accel.intersect({{x, y, 3.0f}, {0, 0, -1}, kInfinity}, hit)) << x << ", " << y;
            EXPECT_TRUE(accel.occluded({{x, y, -2.0f}, vec3(0.0f, 0.0f, 1.0f), kInfinity}));
        }
    }
}

TEST(Accel, DebugQueriesAgreeWithPlainOnes) {
    const Scene scene = icosphere(4);
    const Accelerator accel(scene);
    for (const Ray& ray : random_rays(scene, 500, 11)) {
        Hit plain, counted, recorded;
        TraversalStats stats;
        TraversalRecord record;
        const bool found = accel.intersect(ray, plain);
        EXPECT_EQ(accel.intersect(ray, counted, stats), found);
        EXPECT_EQ(accel.intersect(ray, recorded, record), found);
        EXPECT_EQ(counted.primitive, plain.primitive);
        EXPECT_EQ(recorded.t, plain.t);
        EXPECT_EQ(stats.nodes_visited, record.nodes_visited);
        EXPECT_EQ(stats.triangles_tested, record.triangles_tested);
        ASSERT_EQ(record.visited_nodes.size(), record.nodes_visited);
        EXPECT_EQ(record.visited_nodes.front(), 0u);
        for (uint32_t node : record.visited_nodes) EXPECT_LT(node, accel.stats().nodes);
        for (uint32_t leaf : record.visited_leaves) EXPECT_GE(leaf, accel.stats().nodes);
        if (found) {
            EXPECT_FALSE(record.visited_leaves.empty()) << "a hit is found in a leaf";
        }
        TraversalRecord shadow;
        EXPECT_EQ(accel.occluded(ray, shadow), accel.occluded(ray));
        // Without a hit both queries enter every box the ray meets; with one, the
        // any-hit query takes children in slot order and may visit more or fewer.
        if (!found) {
            EXPECT_EQ(shadow.nodes_visited, record.nodes_visited);
        }
    }
}

TEST(Accel, EmptyScenesWork) {
    const Scene nothing;
    const Accelerator empty(nothing);
    Hit hit;
    EXPECT_FALSE(empty.intersect(Ray{}, hit));
    EXPECT_FALSE(empty.occluded(Ray{}));
    EXPECT_TRUE(empty.boxes(0).nodes.empty());
    EXPECT_EQ(empty.stats().nodes, 0u);

    Scene spheres;
    spheres.spheres = {{{0, 0, 5}, 1.0f, 0}, {{0, 0, 10}, 1.0f, 0}};
    const Accelerator only_spheres(spheres);
    ASSERT_TRUE(only_spheres.intersect(Ray{}, hit));
    EXPECT_EQ(hit.primitive, 0u);
    EXPECT_FLOAT_EQ(hit.t, 4.0f);
    EXPECT_TRUE(only_spheres.occluded(Ray{}));
    EXPECT_FALSE(only_spheres.occluded(Ray{{0, 0, 0}, {0, 0, 1}, 3.5f}));
}

}  // namespace
}  // namespace rt
