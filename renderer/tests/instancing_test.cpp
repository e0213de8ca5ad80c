// Two-level instancing: hits against brute force and against the same scene
// flattened into world triangles, on every SIMD path and thread count; the
// debug queries' counts; the scene's bounds; renders equal to the flattened
// scene's; shadow rays right at every scale through instance transforms; one
// stored copy per shared mesh.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

#include "geometry/accel.h"
#include "geometry/brute_force.h"
#include "instancing_scenes.h"
#include "integrator/render.h"
#include "stability_probes.h"

namespace rt {
namespace {

using namespace rt::testing;

// Rays aimed at the flattened scene's triangles, so that most meet an instance.
std::vector<Ray> rays_for(const Scene& scene, size_t count) { return random_rays(flattened(scene), count, 11); }

TEST(Instancing, HitsMatchBruteForceOnEveryPathAndThreadCount) {
    const Scene scene = instanced_soup(40, 3);
    const std::vector<Ray> rays = rays_for(scene, 4000);
    for (SimdPath path : kSimdPaths) {
        if (!cpu_supports(path)) continue;
        for (unsigned threads : {1u, 2u}) {
            const Accelerator accel(scene, threads, path);
            int failures = 0;
            size_t instance_hits = 0;
            for (const Ray& ray : rays) {
                const Hit expected = brute_force_hit(scene, ray);
                Hit hit;
                const bool found = accel.intersect(ray, hit);
                instance_hits += expected.instance != kNoInstance;
                // Rays through a shared edge may pick either triangle at the same t.
                const bool same = found == expected.found() &&
                                  (!found || (hit.primitive == expected.primitive && hit.instance == expected.instance
                                                  ? hit.t == expected.t && hit.u == expected.u && hit.v == expected.v
                                                  : std::abs(hit.t - expected.t) <= 1e-6f * expected.t)) &&
                                  accel.occluded(ray) == found;
                if (!same && ++failures <= 5)
                    ADD_FAILURE() << to_string(path) << ", " << threads << " threads: BVH " << hit.primitive << "/"
                                  << hit.instance << " at " << hit.t << ", brute force " << expected.primitive << "/"
                                  << expected.instance << " at " << expected.t;
            }
            EXPECT_EQ(failures, 0);
            EXPECT_GT(instance_hits, rays.size() / 4) << "too few rays met an instance to test much";
        }
    }
}

TEST(Instancing, HitsMatchTheFlattenedScene) {
    const Scene scene = instanced_soup(40, 5);
    const Scene flat = flattened(scene);
    const Accelerator accel(scene), flat_accel(flat);
    size_t hits = 0, differ = 0;
    for (const Ray& ray : random_rays(flat, 20000, 13)) {
        Hit a, b;
        const bool found = accel.intersect(ray, a), flat_found = flat_accel.intersect(ray, b);
        hits += found;
        // The same surface, a few ulps apart: the instance's triangles are
        // met in their own space, the flattened ones after rounding to world.
        if (found != flat_found || (found && std::abs(a.t - b.t) > 1e-4f * b.t)) ++differ;
    }
    EXPECT_GT(hits, 5000u);
    EXPECT_LE(differ, hits / 2000) << "of " << hits << " hits";  // grazing rays at silhouettes only
}

TEST(Instancing, DebugQueriesCountWhatThePlainOnesDo) {
    const Scene scene = instanced_soup(30, 7);
    const Accelerator accel(scene, 1);
    const AccelStats& stats = accel.stats();
    size_t tested = 0;
    for (const Ray& ray : rays_for(scene, 500)) {
        Hit plain, counted, recorded;
        TraversalStats counts;
        TraversalRecord record;
        const bool found = accel.intersect(ray, plain);
        EXPECT_EQ(accel.intersect(ray, counted, counts), found);
        EXPECT_EQ(accel.intersect(ray, recorded, record), found);
        EXPECT_EQ(counted.t, plain.t);
        EXPECT_EQ(recorded.instance, plain.instance);
        EXPECT_EQ(record.nodes_visited, counts.nodes_visited);
        EXPECT_EQ(record.triangles_tested, counts.triangles_tested);
        // The ids recorded are the top-level tree's boxes, which boxes() walks.
        EXPECT_LE(record.visited_nodes.size(), record.nodes_visited);
        for (uint32_t node : record.visited_nodes) EXPECT_LT(node, stats.nodes);
        tested += counts.triangles_tested;
        TraversalStats shadow_counts;
        EXPECT_EQ(accel.occluded(ray, shadow_counts), accel.occluded(ray));
    }
    EXPECT_GT(tested, 0u);
    // The top level's leaves count the triangles their instances place.
    const Accelerator::LevelBoxes leaves = accel.boxes(-1);
    uint64_t placed = 0;
    for (uint32_t t : leaves.triangles) placed += t;
    EXPECT_EQ(placed, flattened(scene).triangles.size());
    EXPECT_EQ(leaves.nodes.size(), scene.instances.size() + 1) << "one leaf per instance, and the world tree";
}

// The debugger reaches each entered tree in its own numbering: the boxes a
// ray visited in an instance are boxes(level, instance)'s, and the leaf that
// holds the hit, taken back to world space by the instance's transform, holds
// the world hit point.
TEST(Instancing, RecordsTheTreesEnteredInTheirOwnNumbering) {
    const Scene scene = instanced_soup(30, 7);
    const Accelerator accel(scene, 1);
    std::vector<std::vector<uint32_t>> all_boxes(scene.instances.size());
    size_t checked = 0;
    for (const Ray& ray : rays_for(scene, 400)) {
        Hit hit;
        TraversalRecord record;
        if (!accel.intersect(ray, hit, record) || hit.instance == kNoInstance) continue;
        const auto entered = std::find_if(record.entered.begin(), record.entered.end(),
                                          [&](const EnteredTree& e) { return e.entry == hit.instance; });
        ASSERT_NE(entered, record.entered.end()) << "the hit instance's tree is not among those entered";
        const Accelerator::LevelBoxes leaves = accel.boxes(-1, hit.instance);
        const vec3 local = leaves.to_world.inverse().point(ray.at(hit.t));
        bool holds = false;
        for (uint32_t leaf : entered->visited_leaves) {
            const auto at = std::find(leaves.nodes.begin(), leaves.nodes.end(), leaf);
            ASSERT_NE(at, leaves.nodes.end()) << "visited leaf " << leaf << " is not a leaf of the instance's tree";
            Bounds3 box = leaves.bounds[size_t(at - leaves.nodes.begin())];
            box.min -= vec3(1e-4f), box.max += vec3(1e-4f);
            holds = holds || box.contains(local);
        }
        EXPECT_TRUE(holds) << "no visited leaf holds the hit";
        std::vector<uint32_t>& ids = all_boxes[hit.instance];
        if (ids.empty())
            for (int level = 0; level <= int(leaves.depth); ++level)
                for (uint32_t id : accel.boxes(level, hit.instance).nodes) ids.push_back(id);
        for (uint32_t node : entered->visited_nodes)
            EXPECT_NE(std::find(ids.begin(), ids.end(), node), ids.end()) << "node " << node;
        ++checked;
    }
    EXPECT_GT(checked, 50u);
    for (uint32_t i = 0; i < scene.instances.size(); ++i)
        EXPECT_EQ(accel.boxes(0, i).to_world.translation, scene.instances[i].to_world.translation);
    const Accelerator::LevelBoxes world = accel.boxes(-1, AccelScene::kWorldEntry);
    uint64_t world_triangles = 0;
    for (uint32_t t : world.triangles) world_triangles += t;
    EXPECT_EQ(world_triangles, scene.world_triangles());
    EXPECT_THROW(accel.boxes(0, uint32_t(scene.instances.size())), std::invalid_argument);
}

TEST(Instancing, SceneBoundsHoldEveryPlacedVertex) {
    const Scene scene = instanced_soup(25, 9);
    const Bounds3 bounds = scene.bounds();
    const Scene flat = flattened(scene);
    for (const vec3& p : flat.positions) ASSERT_TRUE(bounds.contains(p));
    // Not much more: instance boxes are their meshes' boxes transformed, at
    // most sqrt(3) times as wide, and the meshes' own-space vertices do not count.
    const Bounds3 flat_bounds = flat.bounds();
    for (int axis = 0; axis < 3; ++axis)
        EXPECT_LE(bounds.extent()[axis], 1.75f * flat_bounds.extent()[axis]) << "axis " << axis;
}

Image render(const Scene& scene, const Camera& camera) {
    const Accelerator accel(scene, 2);
    RenderSettings settings = make_settings(80, 60);
    settings.set_samples_per_pixel(2);
    const Renderer renderer(accel, settings, camera);
    RenderStats counts;
    return renderer.render(2, 16, nullptr, counts);
}

// Shading through the transforms: points, normals (a mirrored instance's
// too) and shadows come out as the flattened scene's.
TEST(Instancing, RendersAsTheFlattenedScene) {
    Scene scene;
    const uint32_t grey = add_material(scene, vec3(0.7f), vec3(0.3f), 30.0f);
    const uint32_t shiny = add_material(scene, vec3(0.2f, 0.4f, 0.8f), vec3(0.6f), 60.0f, vec3(0.3f));
    add_quad(scene, vec3(-6.0f, 0.0f, 6.0f), vec3(12.0f, 0.0f, 0.0f), vec3(0.0f, 0.0f, -12.0f), grey);
    const uint32_t ball = add_shared_mesh(scene, with_radial_normals(icosphere(3)), shiny);
    const uint32_t ring = add_shared_mesh(scene, torus(32, 16, 1.0f, 0.3f), grey);
    for (int i = 0; i < 6; ++i) {
        const float x = -4.0f + 1.6f * float(i);
        scene.instances.push_back(Instance::make(ball, placement({x, 0.8f, -1.0f}, {0, 1, 0}, 0.3f * float(i), vec3(0.8f, 0.8f, 0.6f))));
        scene.instances.push_back(Instance::make(ring, placement({x, 0.3f, 1.5f}, {1, 0, 0}, 1.2f, vec3(i % 2 ? -0.7f : 0.7f, 0.7f, 0.7f))));
    }
    add_point_light(scene, vec3(3.0f, 7.0f, 5.0f), 60.0f);
    const Camera camera = make_camera(vec3(0.0f, 4.0f, 9.0f), vec3(0.0f, 0.5f, 0.0f), 45.0f);
    const Image ours = render(scene, camera), flat = render(flattened(scene), camera);
    double sum = 0.0;
    size_t off = 0;
    for (size_t i = 0; i < ours.rgb.size(); ++i) {
        const double d = std::abs(double(ours.rgb[i]) - double(flat.rgb[i]));
        sum += d;
        off += d > 0.02;
    }
    EXPECT_LT(sum / double(ours.rgb.size()), 1e-3);
    EXPECT_LE(off, ours.rgb.size() / 1000) << "channels more than 0.02 apart";
}

// The stability suite's shadow scenes with the mesh placed by a rotating,
// scaling instance: no lit point shadowed at any scale from 1e-4 to 1e6.
TEST(Instancing, ShadowRaysAreRightThroughTransformsAtEveryScale) {
    for (float scale : shadow_scales()) {
        for (const auto& [name, mesh] : {std::pair<const char*, Scene>{"cube", with_radial_normals(cube())},
                                         std::pair<const char*, Scene>{"icosphere", with_radial_normals(icosphere(3))}}) {
            const vec3 o = kShadowSceneOffset;
            ShadowScene shadow{name, Scene{}, make_camera((o + vec3(3.0f, 2.5f, 4.0f)) * scale, o * scale, 40.0f),
                               (o + vec3(2.0f, 6.0f, 3.0f)) * scale, true};
            const uint32_t shared = add_shared_mesh(shadow.scene, mesh, add_material(shadow.scene, vec3(0.8f)));
            shadow.scene.instances.push_back(Instance::make(shared, placement(o * scale, {1, 2, 3}, 0.7f, vec3(scale))));
            const ShadowTally ours = tally_shadow_rays(shadow, 96).back();
            EXPECT_GT(ours.pixels, 96u * 96u / 8) << name << " at scale " << scale;
            EXPECT_EQ(ours.wrong, 0u) << name << " at scale " << scale;
        }
    }
}

TEST(Instancing, EachSharedMeshIsStoredOnce) {
    Scene scene;
    const uint32_t grey = add_material(scene, vec3(0.7f));
    const uint32_t ball = add_shared_mesh(scene, with_radial_normals(icosphere(3)), grey);
    std::mt19937 rng(1);
    for (int i = 0; i < 200; ++i) scene.instances.push_back(Instance::make(ball, random_placement(rng, 40.0f, false)));
    const Accelerator ours(scene, 1), flat(flattened(scene), 1);
    EXPECT_EQ(ours.stats().triangles, scene.meshes[0].triangle_count);
    EXPECT_EQ(ours.stats().instances, 200u);
    EXPECT_EQ(flat.stats().triangles, 200u * scene.meshes[0].triangle_count);
    const size_t ours_bytes = ours.stats().node_bytes + ours.stats().leaf_bytes;
    const size_t flat_bytes = flat.stats().node_bytes + flat.stats().leaf_bytes;
    EXPECT_LT(ours_bytes * 20, flat_bytes) << ours_bytes << " against " << flat_bytes;
}

TEST(Instancing, MalformedSharedMeshesAreRefused) {
    Scene scene = instanced_soup(3, 1);
    Scene gap = scene;
    gap.meshes[1].first_triangle += 1;
    EXPECT_THROW(Accelerator{gap}, std::invalid_argument);
    Scene beyond = scene;
    beyond.instances[0].mesh = 7;
    EXPECT_THROW(Accelerator{beyond}, std::invalid_argument);
    Scene short_tail = scene;
    short_tail.meshes[1].triangle_count -= 1;
    EXPECT_THROW(Accelerator{short_tail}, std::invalid_argument);
}

}  // namespace
}  // namespace rt
