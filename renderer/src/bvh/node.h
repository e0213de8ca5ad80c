// One BVH node: a box, and where its children or primitives are. 32 bytes, so
// the two children of a node, which are always adjacent, fill 64 bytes that one
// traversal step reads together.
#pragma once

#include <cstdint>

#include "util/bounds.h"

namespace rt::bvh {

struct alignas(32) Node {
    float bounds_min[3];                 // 12 bytes
    uint32_t first_child_or_first_prim;  // 4 bytes: left child (the right one follows it), or first index into Bvh::prim_ids
    float bounds_max[3];                 // 12 bytes
    uint32_t prim_count;                 // 4 bytes: 0 for an interior node

    bool is_leaf() const { return prim_count != 0; }
    uint32_t left_child() const { return first_child_or_first_prim; }
    uint32_t first_prim() const { return first_child_or_first_prim; }

    Bounds3 bounds() const {
        return {vec3(bounds_min[0], bounds_min[1], bounds_min[2]),
                vec3(bounds_max[0], bounds_max[1], bounds_max[2])};
    }

    void set_bounds(const Bounds3& b) {
        for (int axis = 0; axis < 3; ++axis) {
            bounds_min[axis] = b.min[axis];
            bounds_max[axis] = b.max[axis];
        }
    }
};

static_assert(sizeof(Node) == 32);

}  // namespace rt::bvh
