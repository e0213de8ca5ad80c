// The BVH: hits against brute force, build determinism, structural invariants,
// and the SIMD box test against the scalar one.
#include <algorithm>
#include <cstring>
#include <filesystem>
#include <map>
#include <random>
#include <thread>

#include <gtest/gtest.h>

#include "geometry/accel.h"
#include "geometry/brute_force.h"
#include "bvh/binned_sah_builder.h"
#include "bvh/box_test.h"
#include "test_meshes.h"
#include "geometry/triangle.h"

namespace rt {
namespace {

using namespace rt::testing;

// Compares the accelerator with brute force on random rays, reporting the
// first few that disagree.
void expect_matches_brute_force(const Scene& scene, size_t ray_count) {
    const Accelerator accel(scene);
    int failures = 0;
    size_t triangle_hits = 0;
    for (const Ray& ray : random_rays(scene, ray_count, 7)) {
        const Hit expected = brute_force_hit(scene, ray);
        triangle_hits += expected.primitive < scene.triangles.size();
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
    EXPECT_GT(triangle_hits, ray_count / 4) << "too few rays hit a triangle to test much";
}

// Checks the invariants every BVH must keep: boxes nest, leaves bound their
// primitives, and each primitive sits in exactly one leaf.
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
    const Scene scene = random_soup(2000, 6);
    const BuildInput input = build_input(scene);
    const bvh::Bvh bvh = bvh::build_binned_sah(input.bounds, input.centroids);
    const Bounds3 bounds = central_bounds(scene);
    std::vector<Ray> rays = random_rays(scene, 200, 8);
    // Rays lying in the planes of box faces, where the slab test meets 0 * inf.
    for (const bvh::Node& node : {bvh.nodes[1], bvh.nodes[2], bvh.nodes[5]}) {
        for (int axis = 0; axis < 3; ++axis) {
            for (float plane : {node.bounds_min[axis], node.bounds_max[axis]}) {
                vec3 origin = bounds.center();
                origin[axis] = plane;
                vec3 direction(0.0f);
                direction[(axis + 1) % 3] = 1.0f;
                rays.push_back({origin, direction, kInfinity});
                rays.push_back({origin, -direction, kInfinity});
            }
        }
    }
    for (const Ray& ray : rays) {
        const bvh::BoxRay box_ray(ray);
        for (size_t i = 1; i + 1 < bvh.nodes.size(); i += 2) {
            const bvh::ChildEntries simd = bvh::child_entry_distances(&bvh.nodes[i], box_ray, ray.t_max);
            const bvh::ChildEntries scalar = bvh::child_entry_distances_scalar(&bvh.nodes[i], box_ray, ray.t_max);
            ASSERT_EQ(simd.hits, scalar.hits);
            if (scalar.hits & bvh::kHitLeft) {
                ASSERT_EQ(simd.left, scalar.left);
            }
            if (scalar.hits & bvh::kHitRight) {
                ASSERT_EQ(simd.right, scalar.right);
            }
        }
    }
}

}  // namespace
}  // namespace rt
