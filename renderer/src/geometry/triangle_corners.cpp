#include "geometry/triangle_corners.h"

namespace rt {

TriangleCorners triangle_corners(const Scene& scene, const Hit& hit, float time) {
    TriangleCorners c;
    c.vertices = scene.triangles[hit.primitive];
    const bool moving = scene.moving();
    for (int i = 0; i < 3; ++i) {
        const uint32_t v = c.vertices[i];
        c.p[i] = moving ? scene.position_at(v, time) : scene.positions[v];
        c.n[i] = moving ? lerp_position(scene.normals[v], scene.normals_close[v], time) : scene.normals[v];
    }
    const Instance* placed = scene.instance_of(hit.instance);
    if (!placed) return c;
    // Where a moving instance stands at `time`, as the ray met it.
    const Instance moved = placed->moving ? placed->at(time) : Instance{};
    const Instance* instance = placed->moving ? &moved : placed;
    for (int i = 0; i < 3; ++i) {
        const vec3 local = c.p[i];
        c.p[i] = instance->to_world.point(local);
        c.n[i] = try_normalize(instance->normal_to_world() * c.n[i]).value_or(c.n[i]);
        const vec3 error = instance->to_world.point_error(local) +
                           instance->to_world.spread(instance->to_local.point_error(c.p[i]));
        c.placement_error = glm::max(c.placement_error, error);
    }
    return c;
}

}  // namespace rt
