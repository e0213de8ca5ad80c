// Our tree's SAH cost in Embree's own formula, so the two trees' costs can be
// set side by side.
//
// Embree (kernels/bvh/bvh_statistics.{h,cpp}, BVHNStatistics<N>::statistics)
// walks its tree from the root with A = the half area of the box the parent
// stores for the node (the root: the scene's bounds) and sums
//   nodeSAH += A               for every inner node (one box test of its N children),
//   leafSAH += A * blocks      for every leaf of `blocks` primitive blocks
//                              (triangle4: four triangles a block),
// then prints sah = (nodeSAH + leafSAH) / A_root. Both costs are 1: an inner
// node costs what one block of four triangles costs, whatever the width.
// A ray hitting the root enters a box with probability area(box) / area(root),
// so sah is the expected number of node visits plus leaf-block tests of a
// random ray hitting the scene's box.
//
// Our WideBvh has the same shape (eight-wide nodes, leaves of blocks of
// bvh::kBlockWidth = 4 primitives), so the same sum over it is comparable.
#pragma once

#include "bvh/wide_bvh.h"

namespace rt::bench {

double embree_formula_sah(const bvh::WideBvh& bvh);

}  // namespace rt::bench
