// One node of the eight-wide BVH (wide_bvh.h): the boxes of up to eight
// children in structure-of-arrays form, so that one SIMD pass over 8 lanes
// tests the ray against all of them (Embree's BVH8, Wald et al. "Embree: A
// Kernel Framework for Efficient CPU Ray Tracing", 2014), and where each child is.
#pragma once

#include <cstdint>

#include "util/bounds.h"

namespace rt::bvh {

inline constexpr uint32_t kWideWidth = 8;
// Primitives per leaf block: what one SIMD primitive test handles at once.
inline constexpr uint32_t kBlockWidth = 4;
// Blocks a leaf may hold; a leaf reference has 3 bits for the count.
inline constexpr uint32_t kMaxLeafBlocks = 8;
// A padding entry of WideBvh::prim_ids.
inline constexpr uint32_t kNoPrim = 0xffffffffu;

// A child: an inner node's index, or a leaf, a run of blocks of primitives.
struct ChildRef {
    static constexpr uint32_t kLeafBit = 1u << 31;
    static constexpr uint32_t kEmptyBits = 0xffffffffu;
    // Leaves use the leaf bit, 28 bits of first block and 3 of block count.
    static constexpr uint32_t kMaxBlocks = (1u << 28) - 1;

    uint32_t bits = kEmptyBits;

    static ChildRef inner(uint32_t node) { return {node}; }
    static ChildRef leaf(uint32_t first_block, uint32_t block_count) {
        return {kLeafBit | first_block << 3 | (block_count - 1)};
    }

    bool empty() const { return bits == kEmptyBits; }
    bool is_leaf() const { return (bits & kLeafBit) != 0; }
    uint32_t node() const { return bits; }
    uint32_t first_block() const { return (bits & ~kLeafBit) >> 3; }
    uint32_t block_count() const { return (bits & 7u) + 1; }
};

// 224 bytes: seven 32-byte rows, one per plane set and one of references.
// An empty slot has an inverted box (lower +inf, upper -inf), which no ray
// enters, so the box test needs no mask of valid children.
struct alignas(32) WideNode {
    float lower[3][kWideWidth];  // [axis][child]
    float upper[3][kWideWidth];
    ChildRef child[kWideWidth];

    WideNode() {
        for (uint32_t i = 0; i < kWideWidth; ++i) set_child(i, ChildRef{}, Bounds3{});
    }

    void set_child(uint32_t i, ChildRef ref, const Bounds3& b) {
        child[i] = ref;
        for (int axis = 0; axis < 3; ++axis) {
            lower[axis][i] = b.min[axis];
            upper[axis][i] = b.max[axis];
        }
    }

    Bounds3 child_bounds(uint32_t i) const {
        return {vec3(lower[0][i], lower[1][i], lower[2][i]), vec3(upper[0][i], upper[1][i], upper[2][i])};
    }

    uint32_t child_count() const {
        uint32_t n = 0;
        for (const ChildRef& c : child) n += !c.empty();
        return n;
    }

    Bounds3 bounds() const {
        Bounds3 b;
        for (uint32_t i = 0; i < kWideWidth; ++i)
            if (!child[i].empty()) b.extend(child_bounds(i));
        return b;
    }
};

static_assert(sizeof(WideNode) == 224);

// A moving scene's node boxes over the shutter: WideNode holds those at open,
// WideBoxes how far each plane moves by close (close - open, the difference
// the interpolation forms, so that a ray's box test does not). A ray at time
// t tests open + t * motion, which holds every vertex moving in a straight
// line meanwhile: linear bounds per node, as Embree's motion-blur BVHs keep
// them. Far tighter than the union of both boxes when things move by more
// than their size.
struct alignas(32) WideBoxes {
    float lower[3][kWideWidth];
    float upper[3][kWideWidth];

    Bounds3 child_bounds(uint32_t i) const {
        return {vec3(lower[0][i], lower[1][i], lower[2][i]), vec3(upper[0][i], upper[1][i], upper[2][i])};
    }
};

static_assert(sizeof(WideBoxes) == 192);

}  // namespace rt::bvh
