// The BVH and the accelerator: hits against brute force, build determinism,
// structural invariants, level export, and rays through shared edges.
#include <algorithm>
#include <cstring>
#include <filesystem>
#include <map>
#include <random>
#include <thread>

#include <gtest/gtest.h>

#include "accel.h"
#include "bvh/binned_sah_builder.h"
#include "bvh/box_test.h"
#include "loader.h"
#include "triangle.h"

namespace rt {
namespace {

Scene mesh_scene(std::vector<vec3> positions, std::vector<uvec3> triangles) {
    Scene scene;
    scene.normals.assign(positions.size(), vec3(0.0f, 0.0f, 1.0f));
    scene.positions = std::move(positions);
    scene.triangle_materials.assign(triangles.size(), 0);
    scene.triangles = std::move(triangles);
    scene.materials.emplace_back();
    return scene;
}

Scene random_soup(size_t count, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> position(-10.0f, 10.0f);
    std::uniform_real_distribution<float> offset(-1.5f, 1.5f);
    std::vector<vec3> positions;
    std::vector<uvec3> triangles;
    for (uint32_t i = 0; i < count; ++i) {
        const vec3 center(position(rng), position(rng), position(rng));
        for (int k = 0; k < 3; ++k) positions.push_back(center + vec3(offset(rng), offset(rng), offset(rng)));
        triangles.emplace_back(3 * i, 3 * i + 1, 3 * i + 2);
    }
    return mesh_scene(std::move(positions), std::move(triangles));
}

// A closed sphere: the icosahedron with each triangle split in four, `levels` times.
Scene icosphere(int levels, float radius = 1.0f) {
    const float g = (1.0f + std::sqrt(5.0f)) / 2.0f;
    std::vector<vec3> positions = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                                   {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
    std::vector<uvec3> triangles = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                                    {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                                    {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    for (vec3& p : positions) p = radius * glm::normalize(p);
    for (int level = 0; level < levels; ++level) {
        std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoints;
        auto midpoint = [&](uint32_t a, uint32_t b) {
            const auto [it, added] = midpoints.try_emplace({std::min(a, b), std::max(a, b)}, uint32_t(positions.size()));
            if (added) positions.push_back(radius * glm::normalize(positions[a] + positions[b]));
            return it->second;
        };
        std::vector<uvec3> split;
        for (const uvec3& t : triangles) {
            const uint32_t ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
            split.insert(split.end(), {{t[0], ab, ca}, {t[1], bc, ab}, {t[2], ca, bc}, {ab, bc, ca}});
        }
        triangles = std::move(split);
    }
    return mesh_scene(std::move(positions), std::move(triangles));
}

// The cube [-1, 1]^3, each face split along a diagonal.
Scene cube() {
    std::vector<vec3> positions;
    for (int i = 0; i < 8; ++i) positions.emplace_back(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1);
    const std::vector<uvec3> triangles = {{0, 1, 3}, {0, 3, 2}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                                          {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 3, 7}, {1, 7, 5}};
    return mesh_scene(std::move(positions), triangles);
}

// An n x n grid of unit squares in the plane z = 0, two triangles each.
Scene grid(uint32_t n) {
    std::vector<vec3> positions;
    std::vector<uvec3> triangles;
    for (uint32_t y = 0; y <= n; ++y)
        for (uint32_t x = 0; x <= n; ++x) positions.emplace_back(float(x), float(y), 0.0f);
    for (uint32_t y = 0; y < n; ++y) {
        for (uint32_t x = 0; x < n; ++x) {
            const uint32_t v = y * (n + 1) + x;
            triangles.emplace_back(v, v + 1, v + n + 2);
            triangles.emplace_back(v, v + n + 2, v + n + 1);
        }
    }
    return mesh_scene(std::move(positions), std::move(triangles));
}

Scene sample_scene(const char* name) {
    const std::filesystem::path file = std::filesystem::path(RT_SAMPLES_DIR) / name;
    if (!std::filesystem::exists(file))
        throw std::runtime_error(file.string() + " is missing: run `make samples` first");
    return load_scene(file);
}

// The closest hit found by testing every primitive.
Hit brute_force(const Scene& scene, const Ray& ray) {
    Hit hit;
    const WatertightRay watertight(ray);
    for (size_t i = 0; i < scene.triangles.size(); ++i) {
        const uvec3 t = scene.triangles[i];
        TriangleHit th;
        if (intersect_triangle(watertight, scene.positions[t[0]], scene.positions[t[1]], scene.positions[t[2]],
                               std::min(hit.t, ray.t_max), th))
            hit = {th.t, uint32_t(i), th.u, th.v};
    }
    for (size_t s = 0; s < scene.spheres.size(); ++s) {
        Ray clipped = ray;
        clipped.t_max = std::min(hit.t, ray.t_max);
        float t;
        if (intersect_sphere(clipped, scene.spheres[s], t)) hit = {t, uint32_t(scene.triangles.size() + s), 0, 0};
    }
    return hit;
}

// Rays from random points in and around the scene's bounds towards random
// points inside them; every other one ends at a random distance.
std::vector<Ray> random_rays(const Bounds3& bounds, size_t count, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    const vec3 extent = bounds.extent();
    auto point = [&](float margin) {
        const vec3 r(unit(rng), unit(rng), unit(rng));
        return bounds.min - margin * extent + (1.0f + 2.0f * margin) * r * extent;
    };
    std::vector<Ray> rays;
    for (size_t i = 0; i < count; ++i) {
        const vec3 origin = point(0.5f);
        const vec3 target = point(0.0f);
        if (target == origin) continue;
        Ray ray{origin, glm::normalize(target - origin), kInfinity};
        if (i % 2) ray.t_max = unit(rng) * 2.0f * glm::length(extent);
        rays.push_back(ray);
    }
    return rays;
}

Bounds3 scene_bounds(const Scene& scene) {
    Bounds3 bounds;
    for (const vec3& p : scene.positions) bounds.extend(p);
    for (const Sphere& s : scene.spheres) bounds.extend(Bounds3{s.center - s.radius, s.center + s.radius});
    return bounds;
}

// Compares the accelerator with brute force on random rays; returns the
// number of rays that disagree (the first few are reported).
void expect_matches_brute_force(const Scene& scene, size_t ray_count) {
    const Accelerator accel(scene);
    int failures = 0;
    for (const Ray& ray : random_rays(scene_bounds(scene), ray_count, 7)) {
        const Hit expected = brute_force(scene, ray);
        Hit hit;
        const bool found = accel.intersect(ray, hit);
        bool same = found == expected.found();
        if (same && found) {
            // Rays through a shared edge may pick either triangle at the same t.
            same = hit.primitive == expected.primitive
                       ? hit.t == expected.t && hit.u == expected.u && hit.v == expected.v
                       : std::abs(hit.t - expected.t) <= 1e-6f * expected.t;
        }
        same = same && accel.occluded(ray) == found;
        if (!same && ++failures <= 5)
            ADD_FAILURE() << "ray from (" << ray.origin.x << ", " << ray.origin.y << ", " << ray.origin.z
                          << ") t_max " << ray.t_max << ": BVH " << (found ? hit.primitive : kNoPrimitive)
                          << " at t = " << hit.t << ", brute force " << expected.primitive << " at t = "
                          << expected.t << ", occluded " << accel.occluded(ray);
    }
    EXPECT_EQ(failures, 0);
}

// Checks the invariants every BVH must keep and returns the leaves' depths.
void expect_well_formed(const bvh::Bvh& bvh, std::span<const Bounds3> prim_bounds, uint32_t max_leaf_size) {
    ASSERT_FALSE(bvh.empty());
    std::vector<int> times_in_leaf(prim_bounds.size(), 0);
    const std::vector<uint32_t> levels = bvh.node_levels();
    uint32_t deepest = 0;
    for (size_t i = 0; i < bvh.nodes.size(); ++i) {
        const bvh::Node& node = bvh.nodes[i];
        const Bounds3 box = node.bounds();
        deepest = std::max(deepest, levels[i]);
        if (node.is_leaf()) {
            EXPECT_LE(node.prim_count, max_leaf_size) << "leaf " << i;
            for (uint32_t k = node.first_prim(); k < node.first_prim() + node.prim_count; ++k) {
                const Bounds3& prim = prim_bounds[bvh.prim_ids[k]];
                ++times_in_leaf[bvh.prim_ids[k]];
                EXPECT_TRUE(box.contains(prim.min) && box.contains(prim.max)) << "leaf " << i << " misses prim " << k;
            }
            continue;
        }
        ASSERT_GT(node.left_child(), i) << "children must follow their parent";
        ASSERT_LT(node.left_child() + 1, bvh.nodes.size());
        for (uint32_t child : {node.left_child(), node.left_child() + 1}) {
            const Bounds3 child_box = bvh.nodes[child].bounds();
            EXPECT_TRUE(box.contains(child_box.min) && box.contains(child_box.max)) << "node " << child;
        }
    }
    EXPECT_EQ(deepest, bvh.depth);
    EXPECT_LE(bvh.depth, bvh::kMaxDepth);
    for (size_t p = 0; p < times_in_leaf.size(); ++p) EXPECT_EQ(times_in_leaf[p], 1) << "primitive " << p;
}

struct BuildInput {
    std::vector<Bounds3> bounds;
    std::vector<vec3> centroids;
};

BuildInput build_input(const Scene& scene) {
    BuildInput input;
    for (const uvec3& t : scene.triangles) {
        Bounds3 b;
        for (int k = 0; k < 3; ++k) b.extend(scene.positions[t[k]]);
        input.bounds.push_back(b);
        input.centroids.push_back(b.center());
    }
    return input;
}

TEST(Bvh, MatchesBruteForceOnRandomSoup) { expect_matches_brute_force(random_soup(3000, 1), 10000); }
TEST(Bvh, MatchesBruteForceOnIcosphere) { expect_matches_brute_force(icosphere(4), 10000); }
TEST(Bvh, MatchesBruteForceOnGrid) { expect_matches_brute_force(grid(40), 10000); }

TEST(Bvh, MatchesBruteForceWithSpheres) {
    Scene scene = random_soup(500, 2);
    scene.spheres = {{{0, 0, 0}, 3.0f, 0}, {{5, -4, 2}, 1.0f, 0}, {{-8, 8, -8}, 0.5f, 0}};
    expect_matches_brute_force(scene, 10000);
}

TEST(Bvh, MatchesBruteForceOnDragon4) { expect_matches_brute_force(sample_scene("dragon_4.glb"), 10000); }
TEST(Bvh, MatchesBruteForceOnDragon3) { expect_matches_brute_force(sample_scene("dragon_3.glb"), 10000); }
TEST(Bvh, MatchesBruteForceOnBunny) { expect_matches_brute_force(sample_scene("bunny.glb"), 10000); }

TEST(Bvh, BuildIsIndependentOfThreadCount) {
    const BuildInput input = build_input(random_soup(60000, 3));
    bvh::BuildOptions options;
    options.threads = 1;
    const bvh::Bvh sequential = bvh::build_binned_sah(input.bounds, input.centroids, options);
    options.threads = 8;
    const bvh::Bvh parallel = bvh::build_binned_sah(input.bounds, input.centroids, options);
    ASSERT_EQ(sequential.nodes.size(), parallel.nodes.size());
    EXPECT_EQ(0, std::memcmp(sequential.nodes.data(), parallel.nodes.data(), sizeof(bvh::Node) * sequential.nodes.size()));
    EXPECT_EQ(sequential.prim_ids, parallel.prim_ids);
    EXPECT_EQ(sequential.depth, parallel.depth);
}

TEST(Bvh, TreesAreWellFormed) {
    for (const Scene& scene : {random_soup(20000, 4), icosphere(5), grid(64), cube()}) {
        const BuildInput input = build_input(scene);
        const bvh::BuildOptions options;
        expect_well_formed(bvh::build_binned_sah(input.bounds, input.centroids, options), input.bounds,
                           options.max_leaf_size);
    }
}

TEST(Bvh, EqualCentroidsStillGiveSmallLeaves) {
    const BuildInput input = build_input(random_soup(1, 5));
    const std::vector<Bounds3> bounds(1000, input.bounds[0]);
    const std::vector<vec3> centroids(1000, input.centroids[0]);
    const bvh::Bvh bvh = bvh::build_binned_sah(bounds, centroids);
    expect_well_formed(bvh, bounds, bvh::BuildOptions{}.max_leaf_size);
}

TEST(Bvh, SimdBoxTestMatchesScalar) {
    const BuildInput input = build_input(random_soup(2000, 6));
    const bvh::Bvh bvh = bvh::build_binned_sah(input.bounds, input.centroids);
    Bounds3 bounds;
    for (const Bounds3& b : input.bounds) bounds.extend(b);
    std::vector<Ray> rays = random_rays(bounds, 200, 8);
    rays.push_back({vec3(bvh.nodes[1].bounds_max[0], 0, 0), vec3(0, 0, -1), kInfinity});  // in a face's plane
    for (const Ray& ray : rays) {
        const bvh::BoxRay box_ray(ray);
        for (size_t i = 1; i + 1 < bvh.nodes.size(); i += 2) {
            const bvh::ChildEntries simd = bvh::child_entry_distances(&bvh.nodes[i], box_ray, ray.t_max);
            const bvh::ChildEntries scalar = bvh::child_entry_distances_scalar(&bvh.nodes[i], box_ray, ray.t_max);
            ASSERT_EQ(simd.left, scalar.left);
            ASSERT_EQ(simd.right, scalar.right);
        }
    }
}

TEST(Accel, LevelBoxesCoverAllTriangles) {
    const Scene scene = icosphere(4);
    const Accelerator accel(scene);
    const std::vector<uint32_t> levels = accel.bvh().node_levels();
    uint32_t shallowest_leaf = accel.stats().depth;
    for (size_t i = 0; i < levels.size(); ++i)
        if (accel.bvh().nodes[i].is_leaf()) shallowest_leaf = std::min(shallowest_leaf, levels[i]);
    ASSERT_GT(shallowest_leaf, 2u);
    for (int level = 0; level <= int(shallowest_leaf); ++level) {
        const Accelerator::LevelBoxes boxes = accel.boxes(level);
        EXPECT_EQ(boxes.nodes.size(), size_t(1) << level) << "level " << level;
        size_t triangles = 0;
        for (uint32_t count : boxes.triangles) triangles += count;
        EXPECT_EQ(triangles, scene.triangles.size()) << "level " << level;
    }
    const Accelerator::LevelBoxes leaves = accel.boxes(-1);
    EXPECT_EQ(leaves.nodes.size(), accel.stats().leaves);
    size_t triangles = 0;
    for (size_t i = 0; i < leaves.nodes.size(); ++i) {
        triangles += leaves.triangles[i];
        EXPECT_EQ(leaves.triangles[i], accel.bvh().nodes[leaves.nodes[i]].prim_count);
    }
    EXPECT_EQ(triangles, scene.triangles.size());
    EXPECT_TRUE(accel.boxes(int(accel.stats().depth) + 1).nodes.empty());
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

TEST(Accel, HitReportsOriginalTriangleAndBarycentrics) {
    const Scene scene = random_soup(2000, 9);
    const Accelerator accel(scene);
    int hits = 0;
    for (const Ray& ray : random_rays(scene_bounds(scene), 2000, 10)) {
        Hit hit;
        if (!accel.intersect(ray, hit)) continue;
        ++hits;
        const uvec3 t = scene.triangles[hit.primitive];
        const vec3 p = (1.0f - hit.u - hit.v) * scene.positions[t[0]] + hit.u * scene.positions[t[1]] +
                       hit.v * scene.positions[t[2]];
        EXPECT_LT(glm::length(p - ray.at(hit.t)), 1e-3f);
    }
    EXPECT_GT(hits, 100);
}

TEST(Accel, DebugQueriesAgreeWithPlainOnes) {
    const Scene scene = icosphere(4);
    const Accelerator accel(scene);
    for (const Ray& ray : random_rays(scene_bounds(scene), 500, 11)) {
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
        TraversalRecord shadow;
        EXPECT_EQ(accel.occluded(ray, shadow), accel.occluded(ray));
        EXPECT_LE(shadow.nodes_visited, record.nodes_visited);
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
