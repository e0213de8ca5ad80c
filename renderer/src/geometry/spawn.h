// Where a secondary ray starts. Instead of the 2020 report's fixed 0.001 step
// along the ray, the origin moves off the surface along the geometric normal by the
// rounding-error bound of the computed hit point, then one more ulp outward
// (pbrt-v4, "Robust Spawned Ray Origins"). The bound is relative to the point's
// coordinates, so the method is as correct at scale 1e-4 as at 1e5.
#pragma once

#include <bit>
#include <cmath>

#include "util/math.h"
#include "util/ray.h"

namespace rt {

inline float next_float_up(float v) {
    if (std::isinf(v) && v > 0.0f) return v;
    if (v == -0.0f) v = 0.0f;
    uint32_t bits = std::bit_cast<uint32_t>(v);
    bits = v >= 0.0f ? bits + 1 : bits - 1;
    return std::bit_cast<float>(bits);
}

inline float next_float_down(float v) {
    if (std::isinf(v) && v < 0.0f) return v;
    if (v == 0.0f) v = -0.0f;
    uint32_t bits = std::bit_cast<uint32_t>(v);
    bits = v > 0.0f ? bits - 1 : bits + 1;
    return std::bit_cast<float>(bits);
}

// p: the computed hit point; p_error: bound on |p - true point| per axis;
// n: geometric normal; w: direction of the new ray.
inline vec3 offset_ray_origin(vec3 p, vec3 p_error, vec3 n, vec3 w) {
    const float d = glm::dot(glm::abs(n), p_error);
    vec3 offset = d * n;
    if (glm::dot(w, n) < 0.0f) offset = -offset;
    vec3 po = p + offset;
    for (int i = 0; i < 3; ++i) {
        if (offset[i] > 0.0f) po[i] = next_float_up(po[i]);
        else if (offset[i] < 0.0f) po[i] = next_float_down(po[i]);
    }
    return po;
}

// `time`: the shutter time of the ray that found p, which the new ray keeps.
inline Ray spawn_ray(vec3 p, vec3 p_error, vec3 n, vec3 direction, float time) {
    return Ray{offset_ray_origin(p, p_error, n, direction), direction, kInfinity, time};
}

// A ray from a surface point towards `target` that stops just short of it, for
// shadow rays towards a point.
inline Ray spawn_ray_to(vec3 p, vec3 p_error, vec3 n, vec3 target, float time) {
    const vec3 to = target - p;
    const float distance = glm::length(to);
    const vec3 w = to / distance;
    const vec3 origin = offset_ray_origin(p, p_error, n, w);
    return Ray{origin, w, glm::length(target - origin), time};
}

}  // namespace rt
