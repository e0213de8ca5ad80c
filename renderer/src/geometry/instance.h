// A mesh drawn more than once, as glTF nodes that share a mesh draw it: its
// triangles are stored once, in the mesh's own space, and each instance
// places them in the world with an affine transform (Embree's instances;
// pbrt-v4's ObjectInstance). Rays meet an instance in the mesh's space,
// through the inverse transform.
#pragma once

#include <cstdint>

#include "util/bounds.h"
#include "util/math.h"
#include "util/ray.h"

namespace rt {

// An affine map x -> linear * x + translation.
struct Affine {
    glm::mat3 linear{1.0f};
    vec3 translation{0.0f};

    vec3 point(vec3 p) const { return linear * p + translation; }
    vec3 vector(vec3 v) const { return linear * v; }
    // A bound on the rounding of point(p) per axis (pbrt-v4's Transform
    // error: three products and three sums per coordinate).
    vec3 point_error(vec3 p) const {
        const glm::mat3 a(glm::abs(linear[0]), glm::abs(linear[1]), glm::abs(linear[2]));
        return gamma_bound(3) * (a * glm::abs(p) + glm::abs(translation));
    }
    // |linear| applied to a per-axis error: how far an error in the source
    // space can reach in the target space.
    vec3 spread(vec3 error) const {
        const glm::mat3 a(glm::abs(linear[0]), glm::abs(linear[1]), glm::abs(linear[2]));
        return a * error;
    }
    Affine inverse() const {
        const glm::mat3 inv = glm::inverse(linear);
        return {inv, -(inv * translation)};
    }
    Bounds3 box(const Bounds3& b) const {
        Bounds3 out;
        for (int corner = 0; corner < 8; ++corner)
            out.extend(point({corner & 1 ? b.max.x : b.min.x, corner & 2 ? b.max.y : b.min.y, corner & 4 ? b.max.z : b.min.z}));
        // Widened by the rounding, so the box holds every transformed vertex.
        const vec3 slack = point_error(glm::max(glm::abs(b.min), glm::abs(b.max)));
        out.min -= slack;
        out.max += slack;
        return out;
    }
};

// Scene::triangles[first_triangle, first_triangle + triangle_count), in the mesh's own space.
struct SharedMesh {
    uint32_t first_triangle = 0;
    uint32_t triangle_count = 0;
};

// A world ray in a mesh's space. The direction is made unit length again:
// the watertight triangle test's rounding bound (triangle.h) weighs the
// sheared z against x and y as if it were, and refuses every hit of a ray
// shrunk by a large scale. `t_scale` is the mesh-space length of one unit of
// world t: t_world = t_local / t_scale.
struct LocalRay {
    Ray ray;
    float t_scale;
};

// A moving instance's transform is the straight blend of those at shutter
// open and close (Embree's linear instance motion): each placed vertex then
// moves in a straight line, so the top-level boxes at open and close,
// blended, hold the instance at every time.
struct Instance {
    uint32_t mesh = 0;  // into Scene::meshes
    Affine to_world;            // at shutter open, and all the shutter long unless `moving`
    Affine to_local;            // to_world's inverse
    Affine to_world_close;      // at shutter close
    bool moving = false;

    // The instance standing still where it is at `time`.
    Instance at(float time) const {
        if (!moving) return *this;
        const Affine blend{to_world.linear + time * (to_world_close.linear - to_world.linear),
                           to_world.translation + time * (to_world_close.translation - to_world.translation)};
        return make(mesh, blend);
    }

    // The inverse transpose of to_world.linear, which takes normals along.
    glm::mat3 normal_to_world() const { return glm::transpose(to_local.linear); }

    LocalRay local_ray(const Ray& world, float t_max) const {
        if (moving) return at(world.time).local_ray(world, t_max);
        const vec3 direction = to_local.vector(world.direction);
        const float length = glm::length(direction);
        return {Ray{to_local.point(world.origin), direction / length, t_max * length, world.time}, length};
    }

    // Only for invertible transforms (the loader checks them), at open and
    // (for a moving instance) close and between: a blend of two invertible
    // maps can still flatten, which the loader refuses too.
    static Instance make(uint32_t mesh, const Affine& to_world) {
        Instance i;
        i.mesh = mesh;
        i.to_world = to_world;
        i.to_local = to_world.inverse();
        i.to_world_close = to_world;
        return i;
    }
    static Instance make(uint32_t mesh, const Affine& open, const Affine& close) {
        Instance i = make(mesh, open);
        i.to_world_close = close;
        i.moving = open.linear != close.linear || open.translation != close.translation;
        return i;
    }
};

}  // namespace rt
