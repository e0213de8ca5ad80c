// Triangles as the wide BVH's leaves hold them: four to a block, vertex
// coordinates in structure-of-arrays form, so one SSE pass runs the
// watertight test (triangle.h) on all four (Embree's Triangle4v layout).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "bvh/wide_node.h"
#include "util/huge_pages.h"
#include "util/math.h"

namespace rt {

struct alignas(16) TriangleBlock {
    // Set in `prim` when the triangle's material has alpha: its hits go
    // through the hit filter.
    static constexpr uint32_t kAlphaBit = 1u << 31;
    static constexpr uint32_t kEmpty = bvh::kNoPrim;

    float v[3][3][bvh::kBlockWidth];  // [vertex][axis][lane]
    uint32_t prim[bvh::kBlockWidth];  // the scene's triangle number | kAlphaBit, or kEmpty

    // Left unset: make_triangle_blocks sets every field, and zeroing the
    // dragon's 38 MB of blocks first took a tenth of its 2-thread build.
    TriangleBlock() {}

    bool lane_used(uint32_t lane) const { return prim[lane] != kEmpty; }
    uint32_t triangle(uint32_t lane) const { return prim[lane] & ~kAlphaBit; }
    bool has_alpha(uint32_t lane) const { return lane_used(lane) && (prim[lane] & kAlphaBit) != 0; }
    vec3 vertex(uint32_t lane, int k) const { return {v[k][0][lane], v[k][1][lane], v[k][2][lane]}; }
};

static_assert(sizeof(TriangleBlock) == 160);

// One block per kBlockWidth entries of `prim_ids` (a wide BVH's leaf order):
// lane i holds triangle prim_ids[i] with the given vertex positions.
// `alpha[t]` says whether triangle t's hits are filtered (empty: none are).
// On up to `threads` threads (0: all cores) when there are many blocks.
HugePageVector<TriangleBlock> make_triangle_blocks(std::span<const uint32_t> prim_ids, std::span<const vec3> positions,
                                                std::span<const uvec3> triangles, std::span<const uint8_t> alpha,
                                                unsigned threads = 1);

// The blocks' vertex motion over the shutter: close - open per coordinate,
// the difference lerp_position forms, so that open + time * motion is the
// scene's vertex at that time bit for bit.
HugePageVector<TriangleBlock> make_motion_blocks(std::span<const TriangleBlock> open, std::span<const uint32_t> prim_ids,
                                              std::span<const vec3> positions_close, std::span<const uvec3> triangles,
                                              unsigned threads = 1);

}  // namespace rt
