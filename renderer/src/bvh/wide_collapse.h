// Collapses a binary BVH into the eight-wide one the renderer traverses.
//
// Each wide node takes a binary node's two children and keeps opening the
// largest-area inner child among them until it has eight (Wald, Benthin and
// Boulos, "Getting Rid of Packets", 2008; Embree's BVH8 builders do the same
// on the fly). Leaves are copied into blocks of kBlockWidth primitives; a leaf
// too big for kMaxLeafBlocks blocks becomes a subtree of its own.
#pragma once

#include <span>

#include "bvh/bvh.h"
#include "bvh/wide_bvh.h"

namespace rt::bvh {

// prim_bounds are the boxes the binary tree was built over. An inner binary
// node with at most merge_limit primitives under it becomes one leaf.
WideBvh collapse_to_wide(const Bvh& binary, std::span<const Bounds3> prim_bounds, uint32_t merge_limit = kBlockWidth);

}  // namespace rt::bvh
