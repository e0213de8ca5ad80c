// Moving instances: the transform blends from shutter open to close, the top
// level keeps its boxes at both times, and every hit at every time is the one
// brute force finds, or the same scene flattened into moving world triangles
// finds; shading normals follow the instance as it stands then.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "geometry/accel.h"
#include "geometry/brute_force.h"
#include "geometry/surface.h"
#include "instancing_scenes.h"

namespace rt {
namespace {

using namespace rt::testing;

// Rays aimed at the flattened scene, each at a random time of the shutter.
std::vector<Ray> timed_rays(const Scene& scene, size_t count, uint32_t seed) {
    std::vector<Ray> rays = random_rays(flattened(scene), count, seed);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    for (Ray& ray : rays) ray.time = unit(rng);
    return rays;
}

TEST(InstancingMotion, TheBlendStandsWhereOpenAndCloseSay) {
    const Affine open{glm::mat3(2.0f), vec3(1.0f, 0.0f, 0.0f)}, close{glm::mat3(4.0f), vec3(3.0f, 2.0f, 0.0f)};
    const Instance instance = Instance::make(0, open, close);
    ASSERT_TRUE(instance.moving);
    EXPECT_FALSE(Instance::make(0, open, open).moving);
    const vec3 p(1.0f, 1.0f, 1.0f);
    EXPECT_EQ(instance.at(0.0f).to_world.point(p), open.point(p));
    EXPECT_EQ(instance.at(1.0f).to_world.point(p), close.point(p));
    EXPECT_EQ(instance.at(0.5f).to_world.point(p), vec3(5.0f, 4.0f, 3.0f));
    // The ray meets the mesh through the inverse of the blend at its time.
    Ray ray{vec3(5.0f, 4.0f, -10.0f), vec3(0.0f, 0.0f, 1.0f), 100.0f, 0.5f};
    const LocalRay local = instance.local_ray(ray, ray.t_max);
    EXPECT_NEAR(local.ray.origin.x, 1.0f, 1e-6f);
    EXPECT_NEAR(local.ray.origin.y, 1.0f, 1e-6f);
    EXPECT_NEAR(local.t_scale, 1.0f / 3.0f, 1e-6f);
}

TEST(InstancingMotion, HitsMatchBruteForceAtEveryTimeOnEveryPathAndThreadCount) {
    const Scene scene = moving_instanced_soup(40, 3, 3.0f);
    const std::vector<Ray> rays = timed_rays(scene, 4000, 17);
    for (SimdPath path : kSimdPaths) {
        if (!cpu_supports(path)) continue;
        for (unsigned threads : {1u, 2u}) {
            const Accelerator accel(scene, threads, path);
            int failures = 0;
            size_t moving_hits = 0;
            for (const Ray& ray : rays) {
                const Hit expected = brute_force_hit(scene, ray);
                Hit hit;
                const bool found = accel.intersect(ray, hit);
                moving_hits += expected.instance != kNoInstance && scene.instances[expected.instance].moving;
                const bool same = found == expected.found() &&
                                  (!found || (hit.primitive == expected.primitive && hit.instance == expected.instance
                                                  ? hit.t == expected.t
                                                  : std::abs(hit.t - expected.t) <= 1e-6f * expected.t)) &&
                                  accel.occluded(ray) == found;
                if (!same && ++failures <= 5)
                    ADD_FAILURE() << to_string(path) << ", " << threads << " threads, time " << ray.time << ": BVH "
                                  << hit.primitive << "/" << hit.instance << " at " << hit.t << ", brute force "
                                  << expected.primitive << "/" << expected.instance << " at " << expected.t;
            }
            EXPECT_EQ(failures, 0);
            EXPECT_GT(moving_hits, rays.size() / 8) << "too few rays met a moving instance to test much";
        }
    }
}

TEST(InstancingMotion, HitsAndNormalsMatchTheFlattenedMovingScene) {
    const Scene scene = moving_instanced_soup(40, 5, 2.0f);
    const Scene flat = flattened(scene);
    const Accelerator accel(scene), flat_accel(flat);
    size_t hits = 0, differ = 0, normals_off = 0;
    for (const Ray& ray : timed_rays(scene, 20000, 19)) {
        Hit a, b;
        const bool found = accel.intersect(ray, a), flat_found = flat_accel.intersect(ray, b);
        hits += found;
        if (found != flat_found || (found && std::abs(a.t - b.t) > 1e-4f * b.t)) {
            ++differ;
            continue;
        }
        if (!found || a.primitive >= scene.triangles.size()) continue;
        const SurfaceHit sa = surface_at(scene, ray, a), sb = surface_at(flat, ray, b);
        normals_off += glm::dot(sa.ng, sb.ng) < 0.9999f;
    }
    EXPECT_GT(hits, 5000u);
    EXPECT_LE(differ, hits / 2000) << "of " << hits << " hits";  // grazing rays at silhouettes only
    EXPECT_LE(normals_off, hits / 2000) << "of " << hits << " hits";
}

TEST(InstancingMotion, OnlyTheTopLevelMovesWhenOnlyInstancesDo) {
    const Scene scene = moving_instanced_soup(20, 7, 1.0f);
    const Accelerator accel(scene, 1);
    // The scene's bounds hold every instance at close too.
    const Bounds3 bounds = scene.bounds();
    for (const Instance& instance : scene.instances) {
        const Bounds3 close = instance.to_world_close.box(scene.mesh_bounds(instance.mesh));
        EXPECT_TRUE(bounds.contains(close.min) && bounds.contains(close.max));
    }
    // Still trees, whose nodes carry no close boxes: the world soup and both shared meshes.
    const Scene still = instanced_soup(20, 7);
    EXPECT_EQ(accel.stats().leaf_bytes, Accelerator(still, 1).stats().leaf_bytes);
    EXPECT_GT(accel.stats().node_bytes, Accelerator(still, 1).stats().node_bytes) << "the top level's close boxes";
}

}  // namespace
}  // namespace rt
