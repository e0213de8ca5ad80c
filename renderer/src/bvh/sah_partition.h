// The binned SAH builder's partitions of a node's primitives at a split:
// in place for small nodes, block by block into the other buffer for large ones.
#pragma once

#include <emmintrin.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "bvh/fork_join_executor.h"
#include "bvh/sah_bins.h"

namespace rt::bvh::detail {

// Nodes with at least this many primitives are binned in blocks of kBlockSize
// (on as many threads as are spare) and partitioned stably into the other
// buffer; smaller ones are binned in one pass and partitioned in place. Both
// choices depend on the node's size only, which keeps the tree independent of
// the thread count.
constexpr uint32_t kBlockedNodeSize = 1u << 15;
constexpr uint32_t kBlockSize = 1u << 13;

struct Range {
    uint32_t begin;
    uint32_t end;
    uint32_t size() const { return end - begin; }
};

// Moves the primitives left of the split before the others, within the
// range; returns where the right ones begin. Without branches on the side
// a primitive goes to, which no predictor guesses: every primitive is
// swapped with the first right one so far, which moves it there when it
// belongs left and leaves both in place, in effect, when not.
template <typename Ref>
uint32_t partition_in_place(Ref* refs, Range range, const BinMapping& mapping, const Split& split,
                            Box4& left_centroids, Box4& right_centroids) {
    const int axis = split.axis;
    const auto bin = float(split.first_right_bin);
    const __m128 inf = _mm_set1_ps(kInfinity), minus_inf = _mm_set1_ps(-kInfinity);
    uint32_t first_right = range.begin;
    for (uint32_t i = range.begin; i < range.end; ++i) {
        const Ref ref = refs[i];
        const bool left = mapping.below(ref.centroid(axis), axis, bin);
        const __m128 c = ref.centroid4();
        const __m128 is_left = _mm_castsi128_ps(_mm_set1_epi32(-int32_t(left)));
        // inf where the centroid does not count, which no min or max takes.
        left_centroids.lower = _mm_min_ps(_mm_or_ps(_mm_and_ps(is_left, c), _mm_andnot_ps(is_left, inf)),
                                          left_centroids.lower);
        left_centroids.upper = _mm_max_ps(_mm_or_ps(_mm_and_ps(is_left, c), _mm_andnot_ps(is_left, minus_inf)),
                                          left_centroids.upper);
        right_centroids.lower = _mm_min_ps(_mm_or_ps(_mm_andnot_ps(is_left, c), _mm_and_ps(is_left, inf)),
                                           right_centroids.lower);
        right_centroids.upper = _mm_max_ps(_mm_or_ps(_mm_andnot_ps(is_left, c), _mm_and_ps(is_left, minus_inf)),
                                           right_centroids.upper);
        refs[i] = refs[first_right];
        refs[first_right] = ref;
        first_right += left;
    }
    return first_right;
}

// Copies the range into the other buffer, the left primitives first, each
// side in its old order, block by block on as many threads as are spare.
template <typename Ref>
uint32_t partition_blocked(const Ref* src, Ref* dst, Range range, const BinMapping& mapping, const Split& split,
                           const std::vector<BinSet>& block_bins, ForkJoinExecutor& executor,
                           Box4& left_centroids, Box4& right_centroids) {
    const auto block_count = uint32_t(block_bins.size());
    struct BlockOut {
        uint32_t left;   // where the block's left primitives go
        uint32_t right;  // and its right ones
        Box4 left_centroids;
        Box4 right_centroids;
    };
    std::vector<BlockOut> out(block_count);
    uint32_t left_total = 0;
    for (uint32_t b = 0; b < block_count; ++b) {
        out[b].left = range.begin + left_total;
        left_total += block_bins[b].count_below(split.axis, split.first_right_bin);
    }
    const uint32_t middle = range.begin + left_total;
    for (uint32_t b = 0; b < block_count; ++b)
        out[b].right = middle + (b * kBlockSize - (out[b].left - range.begin));
    const int axis = split.axis;
    const auto bin = float(split.first_right_bin);
    executor.parallel_for(block_count, [&](uint32_t block) {
        const uint32_t begin = range.begin + block * kBlockSize;
        const uint32_t end = std::min(range.end, begin + kBlockSize);
        BlockOut& o = out[block];
        uint32_t l = o.left, r = o.right;
        for (uint32_t i = begin; i < end; ++i) {
            const Ref& ref = src[i];
            if (mapping.below(ref.centroid(axis), axis, bin)) {
                o.left_centroids.extend(ref.centroid4());
                dst[l++] = ref;
            } else {
                o.right_centroids.extend(ref.centroid4());
                dst[r++] = ref;
            }
        }
    });
    for (const BlockOut& o : out) {
        left_centroids.extend(o.left_centroids);
        right_centroids.extend(o.right_centroids);
    }
    return middle;
}

}  // namespace rt::bvh::detail
