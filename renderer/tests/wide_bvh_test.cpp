// The eight-wide BVH: its collapse from the binary tree, its leaf blocks, and
// every SIMD path's queries, which must agree with each other bit for bit and
// with brute force.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <vector>

#include "bvh/binned_sah_builder.h"
#include "bvh/wide_collapse.h"
#include "geometry/accel.h"
#include "geometry/brute_force.h"
#include "geometry/triangle_block_test.h"
#include "test_meshes.h"

namespace rt {
namespace {

using namespace rt::testing;

struct Built {
    std::vector<Bounds3> bounds;
    bvh::WideBvh wide;
};

Built build_wide(const Scene& scene, unsigned threads = 1, uint32_t max_leaf_prims = bvh::kBlockWidth) {
    Built built;
    std::vector<vec3> centroids;
    for (const uvec3& t : scene.triangles) {
        Bounds3 b;
        for (int k = 0; k < 3; ++k) b.extend(scene.positions[t[k]]);
        built.bounds.push_back(b);
        centroids.push_back(b.center());
    }
    bvh::BuildOptions options;
    options.threads = threads;
    bvh::CollapseOptions collapse;
    collapse.max_leaf_prims = max_leaf_prims;
    collapse.threads = threads;
    built.wide = bvh::collapse_to_wide(bvh::build_binned_sah(built.bounds, centroids, options), built.bounds, collapse);
    return built;
}

bool contains(const Bounds3& outer, const Bounds3& inner) { return outer.contains(inner.min) && outer.contains(inner.max); }

// Every primitive in exactly one leaf lane, under boxes that hold it; every
// child node after its parent and inside the parent's box of it.
void expect_well_formed(const Built& built, size_t prims) {
    const bvh::WideBvh& wide = built.wide;
    ASSERT_FALSE(wide.empty());
    ASSERT_EQ(wide.prim_ids.size() % bvh::kBlockWidth, 0u);
    std::vector<int> seen(prims, 0);
    for (uint32_t i = 0; i < wide.nodes.size(); ++i) {
        const bvh::WideNode& node = wide.nodes[i];
        EXPECT_GE(node.child_count(), i == 0 ? 1u : 2u) << "node " << i;
        for (uint32_t c = 0; c < bvh::kWideWidth; ++c) {
            const bvh::ChildRef child = node.child[c];
            if (child.empty()) {
                EXPECT_TRUE(node.child_bounds(c).empty()) << "an empty slot's box is inverted";
                continue;
            }
            const Bounds3 box = node.child_bounds(c);
            if (!child.is_leaf()) {
                ASSERT_GT(child.node(), i);
                ASSERT_LT(child.node(), wide.nodes.size());
                EXPECT_TRUE(contains(box, wide.nodes[child.node()].bounds()));
                continue;
            }
            ASSERT_LE(child.block_count(), bvh::kMaxLeafBlocks);
            for (uint32_t b = child.first_block(); b < child.first_block() + child.block_count(); ++b)
                for (uint32_t lane = 0; lane < bvh::kBlockWidth; ++lane) {
                    const uint32_t id = wide.prim_ids[b * bvh::kBlockWidth + lane];
                    if (id == bvh::kNoPrim) continue;
                    ASSERT_LT(id, prims);
                    ++seen[id];
                    EXPECT_TRUE(contains(box, built.bounds[id])) << "primitive " << id;
                }
        }
    }
    for (size_t id = 0; id < prims; ++id) EXPECT_EQ(seen[id], 1) << "primitive " << id;
}

TEST(WideBvh, CollapseKeepsEveryPrimitiveOnceInsideItsBoxes) {
    for (const Scene& scene : {random_soup(3000, 4), icosphere(4), grid(16), random_soup(3, 1), random_soup(1, 2)}) {
        for (uint32_t merge : {0u, bvh::kBlockWidth, 2 * bvh::kBlockWidth}) {
            const Built built = build_wide(scene, 1, merge);
            expect_well_formed(built, scene.triangles.size());
            size_t listed = 0;
            for (const bvh::WideBvh::Box& box : built.wide.boxes()) listed += box.leaf ? box.prims : 0;
            EXPECT_EQ(listed, scene.triangles.size());
            EXPECT_GT(built.wide.sah_cost(1.0, 1.0), 0.0);
        }
    }
}

TEST(WideBvh, ACollapseHasFewerLevelsAndNodesThanTheBinaryTree) {
    const Scene scene = random_soup(20000, 7);
    std::vector<Bounds3> bounds;
    std::vector<vec3> centroids;
    for (const uvec3& t : scene.triangles) {
        Bounds3 b;
        for (int k = 0; k < 3; ++k) b.extend(scene.positions[t[k]]);
        bounds.push_back(b);
        centroids.push_back(b.center());
    }
    const bvh::Bvh binary = bvh::build_binned_sah(bounds, centroids);
    const bvh::WideBvh wide = bvh::collapse_to_wide(binary, bounds);
    size_t inner = 0;
    for (const bvh::Node& node : binary.nodes) inner += !node.is_leaf();
    // Eight children at most, more than two on average: about a third of the
    // levels and under half the inner nodes.
    EXPECT_LT(wide.nodes.size(), inner / 2);
    EXPECT_LE(wide.depth, binary.depth / 2 + 1);
    size_t children = 0;
    for (const bvh::WideNode& node : wide.nodes) children += node.child_count();
    EXPECT_GT(double(children) / double(wide.nodes.size()), 3.0);
}

TEST(WideBvh, PrimitivesNoSplitCanSeparateGetASubtreeOfFullLeaves) {
    // 1000 copies of one triangle: the binary builder's leaf holds them all,
    // more than a wide leaf's eight blocks.
    std::vector<vec3> positions;
    std::vector<uvec3> triangles;
    for (uint32_t i = 0; i < 1000; ++i) {
        positions.insert(positions.end(), {vec3(0, 0, 0), vec3(1, 0, 0), vec3(0, 1, 0)});
        triangles.emplace_back(3 * i, 3 * i + 1, 3 * i + 2);
    }
    const Scene scene = mesh_scene(positions, triangles);
    const Built built = build_wide(scene);
    expect_well_formed(built, scene.triangles.size());
    EXPECT_GT(built.wide.nodes.size(), 1u);
    const Accelerator accel(scene, 1);
    Hit hit;
    ASSERT_TRUE(accel.intersect(Ray{{0.2f, 0.2f, 1.0f}, {0, 0, -1}, kInfinity}, hit));
    EXPECT_EQ(hit.primitive, 0u) << "among equal hits the first triangle wins";
}

TEST(WideBvh, TheTreeIsTheSameForAnyThreadCount) {
    const Scene scene = random_soup(40000, 9);
    const Built one = build_wide(scene, 1), two = build_wide(scene, 2);
    ASSERT_EQ(one.wide.nodes.size(), two.wide.nodes.size());
    EXPECT_EQ(one.wide.prim_ids, two.wide.prim_ids);
    for (size_t i = 0; i < one.wide.nodes.size(); ++i)
        EXPECT_EQ(std::memcmp(&one.wide.nodes[i], &two.wide.nodes[i], sizeof(bvh::WideNode)), 0) << "node " << i;
}

// A moving tree pads the boxes of children that move, against the rounding of
// their interpolation, and leaves those where nothing moves exact and still,
// so that rays leaving a still surface (a floor under a moving mesh) do not
// enter its leaf again.
TEST(WideBvh, MotionPadsOnlyTheChildrenThatMove) {
    Built built = build_wide(random_soup(2000, 6));
    std::vector<Bounds3> close = built.bounds;
    std::vector<uint8_t> moves(close.size(), 0);
    for (size_t p = 0; p < close.size(); p += 3) {
        close[p] = {close[p].min + vec3(0.5f, 0.0f, 0.0f), close[p].max + vec3(0.5f, 0.0f, 0.0f)};
        moves[p] = 1;
    }
    bvh::refit_motion(built.wide, built.bounds, close, moves);
    size_t still_leaves = 0, moving_leaves = 0;
    for (uint32_t i = 0; i < built.wide.nodes.size(); ++i)
        for (uint32_t c = 0; c < bvh::kWideWidth; ++c) {
            const bvh::ChildRef child = built.wide.nodes[i].child[c];
            if (!child.is_leaf() || child.empty()) continue;
            Bounds3 open_union, close_union;
            bool any_moves = false;
            for (uint32_t k = child.first_block() * bvh::kBlockWidth;
                 k < (child.first_block() + child.block_count()) * bvh::kBlockWidth; ++k) {
                const uint32_t id = built.wide.prim_ids[k];
                if (id == bvh::kNoPrim) continue;
                open_union.extend(built.bounds[id]);
                close_union.extend(close[id]);
                any_moves = any_moves || moves[id];
            }
            const Bounds3 at_open = built.wide.nodes[i].child_bounds(c);
            const Bounds3 at_close = built.wide.child_bounds_at_close(i, c);
            if (any_moves) {
                ++moving_leaves;
                EXPECT_TRUE(contains(at_open, open_union) && at_open.min != open_union.min) << "node " << i;
                EXPECT_TRUE(contains(at_close, close_union)) << "node " << i;
            } else {
                ++still_leaves;
                EXPECT_TRUE(at_open.min == open_union.min && at_open.max == open_union.max) << "node " << i;
                EXPECT_TRUE(at_close.min == at_open.min && at_close.max == at_open.max) << "node " << i;
            }
        }
    EXPECT_GT(still_leaves, 0u);
    EXPECT_GT(moving_leaves, 0u);
}

// The four-lane test against the scalar one, lane by lane, bit for bit: on
// rays through random points and exactly through shared edges and vertices,
// where the scalar test's double-precision tie-break decides.
TEST(TriangleBlock, TheFourLaneTestIsTheScalarTestBitForBit) {
    const Scene soup = random_soup(400, 3), sphere = icosphere(2);
    for (const Scene* scene : {&soup, &sphere}) {
        std::vector<uint32_t> ids(scene->triangles.size());
        for (uint32_t i = 0; i < ids.size(); ++i) ids[i] = i;
        while (ids.size() % bvh::kBlockWidth != 0) ids.push_back(bvh::kNoPrim);
        const auto blocks = make_triangle_blocks(ids, scene->positions, scene->triangles, {});
        std::vector<Ray> rays = random_rays(*scene, 300, 5);
        for (const vec3& p : scene->positions) rays.push_back({vec3(0.01f, 0.02f, 0.03f), p, kInfinity});
        uint64_t lanes_hit = 0;
        for (const Ray& ray : rays) {
            const WatertightRay scalar_ray(ray);
            const WatertightRay4 ray4(scalar_ray);
            for (const TriangleBlock& block : blocks) {
                BlockHits hits;
                const uint32_t mask = intersect_block(ray4, block, ray.t_max, hits);
                for (uint32_t lane = 0; lane < bvh::kBlockWidth; ++lane) {
                    if (!block.lane_used(lane)) {
                        EXPECT_FALSE(mask >> lane & 1u);
                        continue;
                    }
                    TriangleHit expected;
                    const bool hit = intersect_triangle(scalar_ray, block.vertex(lane, 0), block.vertex(lane, 1),
                                                        block.vertex(lane, 2), ray.t_max, expected);
                    ASSERT_EQ(bool(mask >> lane & 1u), hit);
                    if (!hit) continue;
                    ++lanes_hit;
                    EXPECT_EQ(hits.t[lane], expected.t);
                    EXPECT_EQ(hits.u[lane], expected.u);
                    EXPECT_EQ(hits.v[lane], expected.v);
                }
            }
        }
        EXPECT_GT(lanes_hit, 100u);
    }
}

// Many blocks are filled on several threads, each a run of its own: the same
// blocks, byte for byte, as on one.
TEST(TriangleBlock, BlocksFilledOnSeveralThreadsAreTheSame) {
    const Scene scene = random_soup(50000, 6);
    std::vector<uint32_t> ids(scene.triangles.size());
    for (uint32_t i = 0; i < ids.size(); ++i) ids[i] = (i * 7919u) % uint32_t(ids.size());
    ids.insert(ids.end(), {bvh::kNoPrim, bvh::kNoPrim});
    while (ids.size() % bvh::kBlockWidth != 0) ids.push_back(bvh::kNoPrim);
    std::vector<uint8_t> alpha(scene.triangles.size());
    for (size_t i = 0; i < alpha.size(); i += 3) alpha[i] = 1;
    const auto one = make_triangle_blocks(ids, scene.positions, scene.triangles, alpha, 1);
    for (unsigned threads : {2u, 3u}) {
        const auto many = make_triangle_blocks(ids, scene.positions, scene.triangles, alpha, threads);
        ASSERT_EQ(one.size(), many.size());
        EXPECT_EQ(std::memcmp(one.data(), many.data(), one.size() * sizeof(TriangleBlock)), 0) << threads << " threads";
    }
}

bool same_bits(const Hit& a, const Hit& b) {
    return a.primitive == b.primitive && std::memcmp(&a.t, &b.t, sizeof(float)) == 0 &&
           std::memcmp(&a.u, &b.u, sizeof(float)) == 0 && std::memcmp(&a.v, &b.v, sizeof(float)) == 0;
}

std::vector<SimdPath> supported_paths() {
    std::vector<SimdPath> paths;
    for (SimdPath path : kSimdPaths)
        if (cpu_supports(path)) paths.push_back(path);
    return paths;
}

// A moving soup with some triangles masked by alpha: every kernel variant.
Scene moving_filtered_soup() {
    Scene scene = random_soup(2000, 13);
    for (const vec3& p : scene.positions) scene.positions_close.push_back(p + vec3(0.5f, 0.0f, -0.25f));
    scene.normals_close = scene.normals;
    scene.materials.push_back(scene.materials[0]);
    scene.materials[1].alpha_mode = AlphaMode::Blend;
    scene.materials[1].alpha = 0.5f;
    for (size_t i = 0; i < scene.triangles.size(); i += 3) scene.triangle_materials[i] = 1;
    return scene;
}

TEST(WideBvh, EverySimdPathGivesTheSameHitsVisitsAndVisibility) {
    const std::vector<SimdPath> paths = supported_paths();
    for (const Scene& scene : {random_soup(5000, 21), icosphere(4), moving_filtered_soup()}) {
        std::vector<Ray> rays = random_rays(scene, 3000, 17);
        std::mt19937 rng(3);
        for (Ray& ray : rays) ray.time = std::uniform_real_distribution<float>(0.0f, 1.0f)(rng);
        const Accelerator reference(scene, 1, SimdPath::generic);
        for (SimdPath path : paths) {
            const Accelerator accel(scene, 2, path);
            for (const Ray& ray : rays) {
                Hit expected, hit;
                TraversalRecord expected_record, record;
                reference.intersect(ray, expected, expected_record);
                accel.intersect(ray, hit, record);
                ASSERT_TRUE(same_bits(hit, expected)) << to_string(path);
                EXPECT_EQ(record.visited_nodes, expected_record.visited_nodes);
                EXPECT_EQ(record.visited_leaves, expected_record.visited_leaves);
                EXPECT_EQ(record.triangles_tested, expected_record.triangles_tested);
                EXPECT_EQ(accel.visibility(ray), reference.visibility(ray)) << to_string(path);
            }
        }
    }
}

TEST(WideBvh, EverySimdPathAgreesWithBruteForce) {
    for (const Scene& scene : {random_soup(3000, 31), icosphere(3)}) {
        for (SimdPath path : supported_paths()) {
            for (unsigned threads : {1u, 2u}) {
                const Accelerator accel(scene, threads, path);
                int wrong = 0;
                for (const Ray& ray : random_rays(scene, 2000, 41)) {
                    Hit hit;
                    const bool found = accel.intersect(ray, hit);
                    const Hit expected = brute_force_hit(scene, ray);
                    wrong += found != expected.found() || (found && hit.t != expected.t);
                    wrong += accel.occluded(ray) != expected.found();
                }
                EXPECT_EQ(wrong, 0) << to_string(path) << ", " << threads << " threads";
            }
        }
    }
}

TEST(WideBvh, AnUnsupportedOrUnknownPathIsRefused) {
    const Scene scene = icosphere(1);
    for (SimdPath path : kSimdPaths) {
        if (!cpu_supports(path)) {
            EXPECT_THROW(Accelerator(scene, 1, path), std::runtime_error);
        }
    }
    EXPECT_NO_THROW(Accelerator(scene, 1, SimdPath::generic));
    EXPECT_STREQ(to_string(SimdPath::generic), "generic");
}

}  // namespace
}  // namespace rt
