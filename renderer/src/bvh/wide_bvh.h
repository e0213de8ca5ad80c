// The eight-wide BVH the renderer traverses, collapsed from the binary SAH tree
// (wide_collapse.h). Like Bvh it is plain data and knows nothing of what the
// primitives are: leaves point at blocks of kBlockWidth entries of prim_ids,
// which the geometry layer turns into its SIMD-ready primitive blocks.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "bvh/wide_node.h"
#include "util/huge_pages.h"

namespace rt::bvh {

// Deepest wide tree: a collapse never deepens the binary one (bvh.h's
// kMaxDepth), but a leaf too big for one wide leaf (primitives no split can
// separate) gets a subtree of its own, at most 11 levels for 2^32 primitives.
// A stack of (kWideWidth - 1) entries per level holds every pending child.
inline constexpr uint32_t kMaxWideDepth = 64 + 12;
inline constexpr uint32_t kWideStackSize = kMaxWideDepth * (kWideWidth - 1) + 1;

struct WideBvh {
    // nodes[0] is the root; every child node comes after its parent. Empty
    // when there are no primitives.
    HugePageVector<WideNode> nodes;
    // One per node for a moving scene (refit_motion), else empty: how far each
    // child's box planes move from shutter open to close.
    HugePageVector<WideBoxes> motion;
    // kBlockWidth entries per block, in leaf order; kNoPrim pads a leaf's last block.
    std::vector<uint32_t> prim_ids;
    uint32_t depth = 0;  // wide levels below the root, leaves counted as a level
    // Whether a closest-hit traversal fetches every child a ray enters
    // before it orders them (wide_traverse.inl). Its user sets it from the
    // size of the tree and its leaves: those that the cache holds gain
    // nothing from the fetches and pay for them.
    bool fetch_ahead = true;

    bool empty() const { return nodes.empty(); }
    size_t block_count() const { return prim_ids.size() / kBlockWidth; }
    size_t leaf_count() const;
    size_t node_bytes() const { return nodes.size() * sizeof(WideNode) + motion.size() * sizeof(WideBoxes); }
    // Child i of `node` at shutter close, as the box test takes it at time 1.
    Bounds3 child_bounds_at_close(uint32_t node, uint32_t i) const {
        const Bounds3 open = nodes[node].child_bounds(i), by = motion[node].child_bounds(i);
        return {open.min + by.min, open.max + by.max};
    }
    // Child i of `node` over the whole shutter interval.
    Bounds3 child_bounds(uint32_t node, uint32_t i) const {
        Bounds3 b = nodes[node].child_bounds(i);
        if (!motion.empty()) b.extend(child_bounds_at_close(node, i));
        return b;
    }

    // The debugger's names for the boxes: node i is i, and a leaf is
    // nodes.size() + its first block, so every box of the tree has one number.
    uint32_t leaf_id(ChildRef leaf) const { return uint32_t(nodes.size()) + leaf.first_block(); }

    // Every box of the tree, parents before children. leaf_prims(leaf) counts
    // a leaf's primitives; by default from prim_ids (which a user of the tree
    // may have dropped once it copied them into its own leaf data).
    struct Box {
        uint32_t id;     // as above
        uint32_t level;  // 0 for the root
        Bounds3 bounds;
        uint32_t prims;  // primitives under it
        bool leaf;
    };
    std::vector<Box> boxes(const std::function<uint32_t(ChildRef)>& leaf_prims = {}) const;

    // Expected cost of a random ray hitting the root: each node costs
    // node_cost per box test of its kWideWidth children and each leaf
    // block_cost per block, weighted by the chance of entering the box.
    double sah_cost(double node_cost, double block_cost) const;
};

// Gives a tree over primitives that move linearly its boxes at shutter open
// (in nodes) and close (in close), from each primitive's box at open and at
// close; `moves[p]` says whether some point of primitive p moves. The box of
// a child that holds a moving primitive is widened by a bound on the
// rounding of the interpolation, so the interpolated box never misses a
// vertex by an ulp. A child where nothing moves keeps its exact box, which
// the interpolation leaves as it is, as it leaves its vertices.
void refit_motion(WideBvh& bvh, std::span<const Bounds3> open, std::span<const Bounds3> close,
                  std::span<const uint8_t> moves);

}  // namespace rt::bvh
