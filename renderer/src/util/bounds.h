// Axis-aligned bounding boxes.
#pragma once

#include "util/math.h"

namespace rt {

struct Bounds3 {
    vec3 min{kInfinity};
    vec3 max{-kInfinity};

    bool empty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
    void extend(vec3 p) { min = glm::min(min, p); max = glm::max(max, p); }
    void extend(const Bounds3& b) { min = glm::min(min, b.min); max = glm::max(max, b.max); }
    vec3 extent() const { return max - min; }
    vec3 center() const { return 0.5f * (min + max); }

    float surface_area() const {
        if (empty()) return 0.0f;
        vec3 e = extent();
        return 2.0f * (e.x * e.y + e.y * e.z + e.z * e.x);
    }

    bool contains(vec3 p) const {
        return p.x >= min.x && p.x <= max.x && p.y >= min.y && p.y <= max.y &&
               p.z >= min.z && p.z <= max.z;
    }
};

inline Bounds3 merge(Bounds3 a, const Bounds3& b) { a.extend(b); return a; }

}  // namespace rt
