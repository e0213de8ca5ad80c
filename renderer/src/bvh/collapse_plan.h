// Which binary nodes become the wide tree's nodes and leaves: the collapse
// with the least SAH cost, by dynamic programming over the binary tree
// (Ylitie, Karras and Laine, "Efficient Incoherent Ray Traversal on GPUs
// Through Compressed Wide BVHs", HPG 2017, section 3.1; gatling's
// src/gi/src/bvh_collapse.c, github.com/pablode/gatling, follows it too).
//
// For each binary node n and each number of slots s (1 to 8) the plan knows
// the cheapest way to hang n's subtree into s child slots of a wide node:
//   C(n, 1) = min(leaf: area(n) * block_cost * blocks(n),
//                 wide node: area(n) * node_cost + D(n, 8))
//   C(n, s) = min(C(n, s - 1), D(n, s))                  for s >= 2
//   D(n, s) = min over k in [1, s) of C(left, k) + C(right, s - k)
// which, from the root's D(root, 8), is the expected cost of a ray through the
// whole wide tree, counted as bench/bvh_bench/ours_sah.h counts it. The greedy
// collapse it replaced (open the widest inner child until there are eight,
// over binary leaves of up to 8) cost 11 to 27% more on the sample meshes.
#pragma once

#include <cstdint>
#include <memory>

#include "bvh/bvh.h"
#include "bvh/wide_node.h"

namespace rt::bvh {

struct CollapseOptions {
    // The largest subtree of several binary leaves that may become one wide
    // leaf (at most kBlockWidth * kMaxLeafBlocks); a binary leaf stays a leaf
    // whatever its size. 1 keeps one primitive a leaf.
    uint32_t max_leaf_prims = 2 * kBlockWidth;
    // SAH costs of entering a wide node (its eight box tests) and of testing
    // one leaf block.
    float node_cost = 1.0f;
    float block_cost = 1.0f;
    unsigned threads = 0;  // 0: all cores; the plan is the same for any count
};

class CollapsePlan {
  public:
    CollapsePlan(const Bvh& binary, const CollapseOptions& options);

    uint32_t prims(uint32_t node) const { return prims_[node]; }
    // Where the node's primitives start in the binary tree's prim_ids.
    uint32_t first_prim(uint32_t node) const { return first_[node]; }
    // Whether the node, given one slot, is a leaf rather than a wide node.
    bool is_leaf(uint32_t node) const { return (choice_[node] & kLeafBit) != 0; }
    // How many of `slots` slots (2 to 8) the left child of inner node `node`
    // takes at the cheapest; 0 when `node` is as cheap in slots - 1 slots.
    uint32_t left_slots(uint32_t node, uint32_t slots) const { return (choice_[node] >> (3 * (slots - 2))) & 7u; }
    // How many of its own wide node's slots the left child of inner node `node` takes.
    uint32_t wide_left_slots(uint32_t node) const { return (choice_[node] >> kWideShift) & 7u; }
    // SAH cost of the wide tree, over the root's area, as WideBvh::sah_cost
    // counts it (but for binary leaves too big for one wide leaf).
    double root_cost() const { return root_cost_; }

  private:
    class Planner;

    // choice_ bits: three per slot count s in [2, 8] (from bit 3 * (s - 2)),
    // the left child's share of s slots or 0; three for the split of the
    // node's own wide node; and the leaf bit.
    static constexpr uint32_t kWideShift = 21;
    static constexpr uint32_t kLeafBit = 1u << 31;

    std::unique_ptr<uint32_t[]> prims_;
    std::unique_ptr<uint32_t[]> first_;
    std::unique_ptr<uint32_t[]> choice_;
    double root_cost_ = 0.0;
};

}  // namespace rt::bvh
