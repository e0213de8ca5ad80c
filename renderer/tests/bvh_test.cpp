// The BVH: hits against brute force, build determinism, structural invariants,
// the builder's SAH against a plain binned builder, its leaf block pricing,
// and the SIMD box test against the scalar one.
#include <algorithm>
#include <cstring>
#include <filesystem>
#include <map>
#include <random>
#include <span>
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

// Each primitive's centroid moved off its box's centre (still inside), so that
// the builder cannot derive centroids from boxes.
std::vector<vec3> off_centre_centroids(const BuildInput& input) {
    std::vector<vec3> centroids;
    for (const Bounds3& b : input.bounds) centroids.push_back(b.min + 0.3f * b.extent());
    return centroids;
}

void expect_same_tree(const bvh::Bvh& a, const bvh::Bvh& b) {
    ASSERT_EQ(a.nodes.size(), b.nodes.size());
    EXPECT_EQ(0, std::memcmp(a.nodes.data(), b.nodes.data(), sizeof(bvh::Node) * a.nodes.size()));
    EXPECT_EQ(a.prim_ids, b.prim_ids);
    EXPECT_EQ(a.depth, b.depth);
}

// A plain binned SAH builder, written for clarity: every node's bounds from
// its primitives, 32 bins on all three axes, primitives priced one each. The
// builder under test must find trees at least as cheap.
struct ReferenceBuilder {
    std::span<const Bounds3> bounds;
    std::span<const vec3> centroids;
    float traversal_cost;
    uint32_t max_leaf_size;
    bvh::Bvh bvh;

    static constexpr uint32_t kBins = 32;

    bvh::Bvh run() {
        for (uint32_t i = 0; i < bounds.size(); ++i) bvh.prim_ids.push_back(i);
        bvh.nodes.resize(1);
        build(0, 0, uint32_t(bounds.size()));
        for (uint32_t level : bvh.node_levels()) bvh.depth = std::max(bvh.depth, level);
        return std::move(bvh);
    }

    void build(uint32_t index, uint32_t begin, uint32_t end) {
        Bounds3 box, centroid_box;
        for (uint32_t i = begin; i < end; ++i) {
            box.extend(bounds[bvh.prim_ids[i]]);
            centroid_box.extend(centroids[bvh.prim_ids[i]]);
        }
        bvh.nodes[index].set_bounds(box);
        bvh.nodes[index].first_child_or_first_prim = begin;
        bvh.nodes[index].prim_count = end - begin;
        const uint32_t count = end - begin;
        if (count == 1) return;
        float best_cost = kInfinity;
        int best_axis = -1;
        float best_position = 0.0f;
        for (int axis = 0; axis < 3; ++axis) {
            const float extent = centroid_box.extent()[axis];
            if (!(extent > 0.0f)) continue;
            for (uint32_t b = 1; b < kBins; ++b) {
                const float position = centroid_box.min[axis] + extent * float(b) / float(kBins);
                Bounds3 left, right;
                uint32_t left_count = 0;
                for (uint32_t i = begin; i < end; ++i) {
                    const uint32_t id = bvh.prim_ids[i];
                    if (centroids[id][axis] < position) {
                        left.extend(bounds[id]);
                        ++left_count;
                    } else {
                        right.extend(bounds[id]);
                    }
                }
                if (left_count == 0 || left_count == count) continue;
                const float cost = left.surface_area() * float(left_count) +
                                   right.surface_area() * float(count - left_count);
                if (cost < best_cost) best_cost = cost, best_axis = axis, best_position = position;
            }
        }
        const float area = box.surface_area();
        if (count <= max_leaf_size && !(traversal_cost * area + best_cost < float(count) * area)) return;
        uint32_t middle = begin + count / 2;
        if (best_axis >= 0) {
            middle = uint32_t(std::partition(bvh.prim_ids.begin() + begin, bvh.prim_ids.begin() + end,
                                             [&](uint32_t id) { return centroids[id][best_axis] < best_position; }) -
                              bvh.prim_ids.begin());
        }
        const auto children = uint32_t(bvh.nodes.size());
        bvh.nodes.resize(children + 2);
        bvh.nodes[index].first_child_or_first_prim = children;
        bvh.nodes[index].prim_count = 0;
        build(children, begin, middle);
        build(children + 1, middle, end);
    }
};

std::map<uint32_t, size_t> leaf_size_histogram(const bvh::Bvh& bvh) {
    std::map<uint32_t, size_t> sizes;
    for (const bvh::Node& node : bvh.nodes)
        if (node.is_leaf()) ++sizes[node.prim_count];
    return sizes;
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

// 150000 primitives: the largest nodes are binned and partitioned block by
// block, on several threads where there are.
TEST(Bvh, BuildIsIndependentOfThreadCount) {
    const BuildInput input = build_input(random_soup(150000, 3));
    bvh::BuildOptions options;
    options.threads = 1;
    const bvh::Bvh sequential = bvh::build_binned_sah(input.bounds, input.centroids, options);
    for (unsigned threads : {2u, 3u, 8u}) {
        SCOPED_TRACE(threads);
        options.threads = threads;
        expect_same_tree(sequential, bvh::build_binned_sah(input.bounds, input.centroids, options));
    }
}

TEST(Bvh, BuildIsIndependentOfThreadCountWithOffCentreCentroids) {
    const BuildInput input = build_input(random_soup(80000, 9));
    const std::vector<vec3> centroids = off_centre_centroids(input);
    bvh::BuildOptions options;
    options.leaf_block_size = 4;
    options.threads = 1;
    const bvh::Bvh sequential = bvh::build_binned_sah(input.bounds, centroids, options);
    options.threads = 4;
    expect_same_tree(sequential, bvh::build_binned_sah(input.bounds, centroids, options));
}

TEST(Bvh, BuildIsIndependentOfThreadCountOnDragon3) {
    const BuildInput input = build_input(sample_scene("dragon_3.glb"));
    bvh::BuildOptions options;
    options.traversal_cost = 2.0f;
    options.threads = 1;
    const bvh::Bvh sequential = bvh::build_binned_sah(input.bounds, input.centroids, options);
    options.threads = 2;
    expect_same_tree(sequential, bvh::build_binned_sah(input.bounds, input.centroids, options));
}

TEST(Bvh, SahNoWorseThanPlainBinnedBuilder) {
    for (const Scene& scene : {random_soup(5000, 10), icosphere(4), grid(50)}) {
        const BuildInput input = build_input(scene);
        for (float traversal_cost : {1.0f, 2.0f}) {
            bvh::BuildOptions options;
            options.traversal_cost = traversal_cost;
            const bvh::Bvh built = bvh::build_binned_sah(input.bounds, input.centroids, options);
            const bvh::Bvh reference =
                ReferenceBuilder{input.bounds, input.centroids, traversal_cost, options.max_leaf_size, {}}.run();
            expect_well_formed(reference, input.bounds, options.max_leaf_size);
            // The reference places bin boundaries by a differently rounded
            // formula, so its trees may be a hair cheaper or dearer.
            EXPECT_LE(built.sah_cost(traversal_cost), reference.sah_cost(traversal_cost) * (1.0 + 1e-3))
                << scene.triangles.size() << " triangles, traversal cost " << traversal_cost;
        }
    }
}

// Pricing leaves by blocks of 4 favours leaves that fill blocks: leaves of 1
// to 3 primitives become rarer, and the tree stays well formed.
TEST(Bvh, LeafBlocksFavourFullBlocks) {
    const BuildInput input = build_input(random_soup(20000, 11));
    bvh::BuildOptions options;
    options.traversal_cost = 2.0f;
    const bvh::Bvh single = bvh::build_binned_sah(input.bounds, input.centroids, options);
    options.leaf_block_size = 4;
    const bvh::Bvh blocks = bvh::build_binned_sah(input.bounds, input.centroids, options);
    expect_well_formed(blocks, input.bounds, options.max_leaf_size);
    auto partial_blocks = [](const bvh::Bvh& bvh) {
        size_t partial = 0, leaves = 0;
        for (const auto& [size, count] : leaf_size_histogram(bvh)) {
            leaves += count;
            if (size < 4) partial += count;
        }
        return double(partial) / double(leaves);
    };
    EXPECT_LT(partial_blocks(blocks), 0.5 * partial_blocks(single));
    EXPECT_LT(blocks.leaf_count(), single.leaf_count());
}

// Blocks of one primitive costing 1 are the plain SAH: the same tree as the
// defaults; and scaling both costs by 2, exactly, changes no decision.
TEST(Bvh, LeafBlockDefaultsAreThePlainSah) {
    const BuildInput input = build_input(random_soup(20000, 12));
    bvh::BuildOptions options;
    const bvh::Bvh plain = bvh::build_binned_sah(input.bounds, input.centroids, options);
    options.leaf_block_size = 1;
    options.block_cost = 1.0f;
    expect_same_tree(plain, bvh::build_binned_sah(input.bounds, input.centroids, options));
    options.leaf_block_size = 0;  // counts as 1
    expect_same_tree(plain, bvh::build_binned_sah(input.bounds, input.centroids, options));
    options.block_cost = 2.0f;
    options.traversal_cost = 2.0f;
    expect_same_tree(plain, bvh::build_binned_sah(input.bounds, input.centroids, options));
}

TEST(Bvh, TreesAreWellFormed) {
    for (const Scene& scene : {random_soup(20000, 4), random_soup(70000, 13), icosphere(5), grid(64), cube()}) {
        const BuildInput input = build_input(scene);
        for (uint32_t leaf_block_size : {1u, 4u}) {
            bvh::BuildOptions options;
            options.leaf_block_size = leaf_block_size;
            expect_well_formed(bvh::build_binned_sah(input.bounds, input.centroids, options), input.bounds,
                               options.max_leaf_size);
            expect_well_formed(bvh::build_binned_sah(input.bounds, off_centre_centroids(input), options),
                               input.bounds, options.max_leaf_size);
        }
    }
}

TEST(Bvh, EqualCentroidsStillGiveSmallLeaves) {
    const BuildInput input = build_input(random_soup(1, 5));
    const std::vector<Bounds3> bounds(1000, input.bounds[0]);
    const std::vector<vec3> centroids(1000, input.centroids[0]);
    const bvh::Bvh bvh = bvh::build_binned_sah(bounds, centroids);
    expect_well_formed(bvh, bounds, bvh::BuildOptions{}.max_leaf_size);
}

// Enough of them that the top nodes take the blocked path, which halves them too.
TEST(Bvh, ManyEqualCentroidsStillGiveSmallLeaves) {
    const BuildInput input = build_input(random_soup(1, 5));
    const std::vector<Bounds3> bounds(70000, input.bounds[0]);
    const std::vector<vec3> centroids(70000, input.centroids[0]);
    bvh::BuildOptions options;
    options.threads = 1;
    const bvh::Bvh bvh = bvh::build_binned_sah(bounds, centroids, options);
    expect_well_formed(bvh, bounds, options.max_leaf_size);
    options.threads = 2;
    expect_same_tree(bvh, bvh::build_binned_sah(bounds, centroids, options));
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
