// Top-down BVH build with the surface area heuristic evaluated on bins of the
// centroid bounds (Wald, "On fast Construction of SAH-based Bounding Volume
// Hierarchies", 2007), over all three axes.
//
// Subtrees are built in parallel, yet the tree depends only on the input: each
// subtree writes into a range of node slots fixed by its primitive count, and a
// last pass packs the slots in depth-first order. One thread or many give the
// same nodes, bit for bit.
#pragma once

#include <cstdint>
#include <span>

#include "util/bounds.h"
#include "bvh/bvh.h"
#include "util/math.h"

namespace rt::bvh {

struct BuildOptions {
    uint32_t bin_count = 32;  // at most 32
    // Leaves are as small as the SAH finds cheapest, but never larger than this
    // unless their primitives cannot be told apart (equal centroids deep down).
    uint32_t max_leaf_size = 8;
    // Cost of visiting a node relative to testing one primitive.
    float traversal_cost = 1.0f;
    unsigned threads = 0;  // 0: all cores
};

// prim_bounds[i] and centroids[i] describe primitive i; centroids must lie
// inside their bounds.
Bvh build_binned_sah(std::span<const Bounds3> prim_bounds, std::span<const vec3> centroids,
                     const BuildOptions& options = {});

}  // namespace rt::bvh
