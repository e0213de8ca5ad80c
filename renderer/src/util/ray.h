// A ray and what a closest-hit query returns.
#pragma once

#include "util/math.h"

namespace rt {

// direction is unit length wherever the renderer makes rays, so t is a distance.
struct Ray {
    vec3 origin{0.0f};
    vec3 direction{0.0f, 0.0f, 1.0f};
    float t_max = kInfinity;
    // When in the shutter interval the ray is traced, 0 (open) to 1 (close):
    // the moment the scene's moving vertices are taken at. Secondary rays keep
    // their camera ray's.
    float time = 0.0f;

    vec3 at(float t) const { return origin + t * direction; }
};

inline constexpr uint32_t kNoPrimitive = 0xffffffffu;
inline constexpr uint32_t kNoInstance = 0xffffffffu;

// Primitives are numbered triangles first, then spheres. (u, v) are the
// barycentric weights of a triangle's second and third vertex, or the sphere's
// (unused) parametrisation.
struct Hit {
    float t = kInfinity;
    uint32_t primitive = kNoPrimitive;
    float u = 0.0f;
    float v = 0.0f;
    // The Scene::instances entry that placed the triangle, kNoInstance for the
    // scene's own world-space triangles and its spheres.
    uint32_t instance = kNoInstance;

    bool found() const { return primitive != kNoPrimitive; }
};

}  // namespace rt
