// Collapses a binary BVH into the eight-wide one the renderer traverses, as
// its collapse plan (collapse_plan.h) says: the wide tree of least SAH cost
// whose nodes and leaves are binary nodes. Leaves are copied into blocks of
// kBlockWidth primitives; a binary leaf too big for kMaxLeafBlocks blocks
// becomes a subtree of its own.
#pragma once

#include <span>

#include "bvh/bvh.h"
#include "bvh/collapse_plan.h"
#include "bvh/wide_bvh.h"

namespace rt::bvh {

// prim_bounds are the boxes the binary tree was built over.
WideBvh collapse_to_wide(const Bvh& binary, std::span<const Bounds3> prim_bounds, const CollapseOptions& options = {});

}  // namespace rt::bvh
