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

inline Hit brute_force_hit(const Scene& scene, const Ray& ray) {
    Hit hit;
    const WatertightRay watertight(ray);
    for (size_t i = 0; i < scene.triangles.size(); ++i) {
        const uvec3 t = scene.triangles[i];
        const auto vertex = [&](uint32_t v) {
            return scene.moving() ? scene.position_at(v, ray.time) : scene.positions[v];
        };
        TriangleHit th;
        if (intersect_triangle(watertight, vertex(t[0]), vertex(t[1]), vertex(t[2]), std::min(hit.t, ray.t_max), th))
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

}  // namespace rt
