// Top-down BVH build with the surface area heuristic evaluated on bins of the
// centroid bounds (Wald, "On fast Construction of SAH-based Bounding Volume
// Hierarchies", 2007), over all three axes.
//
// Subtrees are built in parallel, and the largest nodes are binned and
// partitioned by all threads at once, yet the tree depends only on the input:
// how a node's primitives are binned and partitioned depends on its size alone,
// never on how many threads help; each subtree writes into a range of node
// slots fixed by its primitive count, and a last pass packs the slots in
// depth-first order. One thread or many give the same nodes, bit for bit.
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
    // many primitives unless their primitives cannot be told apart (equal
    // centroids deep down).
    uint32_t max_leaf_size = 8;
    // Cost of visiting a node, in the units block_cost is in (with the
    // defaults, relative to testing one primitive).
    float traversal_cost = 1.0f;
    // How the SAH prices primitives, in a leaf and on either side of a
    // candidate split: n primitives cost ceil(n / leaf_block_size) block tests
    // of block_cost each, for leaves whose primitives are tested
    // leaf_block_size at a time (a SIMD test of 4 triangles: 4, where a leaf
    // of 1 to 4 costs one test, of 5 to 8 two). The defaults price each
    // primitive at 1: the plain SAH, and the same tree as without these
    // options. Bvh::sah_cost still counts primitives one by one.
    uint32_t leaf_block_size = 1;  // 0 counts as 1
    float block_cost = 1.0f;
    unsigned threads = 0;  // 0: all cores
};

// prim_bounds[i] and centroids[i] describe primitive i; centroids must lie
// inside their bounds.
Bvh build_binned_sah(std::span<const Bounds3> prim_bounds, std::span<const vec3> centroids,
                     const BuildOptions& options = {});

}  // namespace rt::bvh
