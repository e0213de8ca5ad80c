// The ray/triangle test most ray tracers start with: Möller and Trumbore, "Fast,
// Minimum Storage Ray/Triangle Intersection" (1997), as it is usually copied
// (two-sided, machine epsilon for the parallel test and the near end). A
// reference to measure the watertight test against, never used to render:
// each triangle computes its barycentrics in its own frame, so a ray through a
// shared edge can find itself outside both triangles.
#pragma once

#include <limits>

#include "util/math.h"
#include "util/ray.h"

namespace rt::testing {

inline bool moller_trumbore(const Ray& ray, vec3 p0, vec3 p1, vec3 p2, float t_max, float& t) {
    constexpr float kEpsilon = std::numeric_limits<float>::epsilon();
    const vec3 edge1 = p1 - p0;
    const vec3 edge2 = p2 - p0;
    const vec3 h = glm::cross(ray.direction, edge2);
    const float a = glm::dot(edge1, h);
    if (a > -kEpsilon && a < kEpsilon) return false;
    const float f = 1.0f / a;
    const vec3 s = ray.origin - p0;
    const float u = f * glm::dot(s, h);
    if (u < 0.0f || u > 1.0f) return false;
    const vec3 q = glm::cross(s, edge1);
    const float v = f * glm::dot(ray.direction, q);
    if (v < 0.0f || u + v > 1.0f) return false;
    t = f * glm::dot(edge2, q);
    return t > kEpsilon && t < t_max;
}

}  // namespace rt::testing
