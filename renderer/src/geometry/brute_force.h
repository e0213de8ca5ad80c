// The closest hit found by testing every primitive: the reference the BVH is
// checked against (bvh_test) and the arbiter where we and Embree differ
// (bvh_bench). Never used to render.
#pragma once

#include <algorithm>

#include "geometry/accel.h"
#include "geometry/scene.h"
#include "geometry/sphere.h"
#include "geometry/triangle.h"

namespace rt {

// Triangles [first, first + count) against a ray in their space, whose t is
// t_scale times the world ray's; instance is the Hit's instance number for them.
inline void brute_force_triangles(const Scene& scene, const Ray& ray, float t_scale, size_t first, size_t count,
                                  uint32_t instance, Hit& hit) {
    const WatertightRay watertight(ray);
    for (size_t i = first; i < first + count; ++i) {
        const uvec3 t = scene.triangles[i];
        const auto vertex = [&](uint32_t v) {
            return scene.moving() ? scene.position_at(v, ray.time) : scene.positions[v];
        };
        TriangleHit th;
        if (intersect_triangle(watertight, vertex(t[0]), vertex(t[1]), vertex(t[2]),
                               std::min(hit.t * t_scale, ray.t_max), th) &&
            th.t / t_scale < hit.t)
            hit = {th.t / t_scale, uint32_t(i), th.u, th.v, instance};
    }
}

inline Hit brute_force_hit(const Scene& scene, const Ray& ray) {
    Hit hit;
    brute_force_triangles(scene, ray, 1.0f, 0, scene.world_triangles(), kNoInstance, hit);
    // Each instance in the mesh's space, as the accelerator meets it.
    for (uint32_t i = 0; i < scene.instances.size(); ++i) {
        const Instance& instance = scene.instances[i];
        const LocalRay local = instance.local_ray(ray, ray.t_max);
        const SharedMesh& mesh = scene.meshes[instance.mesh];
        brute_force_triangles(scene, local.ray, local.t_scale, mesh.first_triangle, mesh.triangle_count, i, hit);
    }
    for (size_t s = 0; s < scene.spheres.size(); ++s) {
        Ray clipped = ray;
        clipped.t_max = std::min(hit.t, ray.t_max);
        float t;
        if (intersect_sphere(clipped, scene.spheres[s], t)) hit = {t, uint32_t(scene.triangles.size() + s), 0, 0};
    }
    return hit;
}

}  // namespace rt
