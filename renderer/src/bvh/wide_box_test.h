// The ray against the eight child boxes of a wide node: the slab test of
// box_test.h, lane by lane, with the same operations in the same order on
// every SIMD path, so each enters the same boxes at the same distances, bit
// for bit. One difference from box_test.h: an exit distance is
// (plane - origin) * (inv_direction * kExitScale), the scale folded into the
// reciprocal once per ray rather than applied to every distance. Both forms
// round four times in all (the subtraction, the reciprocal, two products),
// so the same scale bounds both, and a node test takes three products fewer
// (occlusion queries 3-5% faster on the dragons).
//
// The distances are reduced as integers: a float >= +0 orders as its bits
// do, and a negative one has its sign bit set, as have -0 and the NaN that
// 0 * inf makes (x86's default NaN), so each loses a signed maximum to +0.
// The entry distance is then the scalar test's, bit for bit, from integer
// maxima of one cycle each rather than a chain of float maxima of four. The
// exit planes take a float minimum with t_max first, which drops a NaN as
// box_test.h does;
// the integer minimum of what is left may pick a different negative than
// the float one would, and treats -0 as negative: either way the ray leaves
// the box by t = 0, where no hit counts, so only boxes touched at t = 0 and
// left at once are passed over. A ray waits on its node tests one after
// another, so their latency bounds it (Embree's BVH8 kernels take maxi, mini
// and an integer compare for the same reason): 1T against rtcIntersect1 on
// the Xeon, 3 rounds, diffuse rays on dragon_4 0.86 -> 0.89, random rays
// 1.31 -> 1.36, camera rays alike; the packets' interval and ray tests
// (packet_lanes.inl, slab_entry) 0-2% faster.
//
// Not Embree's fused form, plane * inv_direction - origin * inv_direction in
// one multiply-add. Rounding origin * inv_direction errs by up to half an
// ulp of it, which is not small against a distance when the origin is far
// from the world's origin, so a conservative test must pad that term apart
// for entry and exit planes (three more per-ray registers). A ray with a
// direction component of 0 has no fused form at all: 0 * inf gives NaN, and
// a finite stand-in for the reciprocal makes a ray in a box's face plane
// leave the box at t = 0, so it needs the (plane - origin) form besides.
// Measured on the Xeon, 1T against rtcIntersect1, dragon_4: without pads or
// the zero case (not conservative, a bound only) diffuse rays 0.92 -> 0.96
// and camera rays 1.08 -> 1.14, but random rays 1.36 -> 1.30; with them, by
// one traversal per form chosen per ray, diffuse 0.92 -> 0.91, camera rays
// 1.08 -> 1.04, random rays 1.35 -> 1.23 (the padded constants spill, and
// each kernel is twice the code).
//
// This header has the per-ray constants and the SSE2 test, which every x86-64
// runs; wide_box_test_avx2.inl has the one-register AVX2 test.
#pragma once

#include <emmintrin.h>

#include <cstddef>
#include <cstdint>

#include "bvh/box_test.h"
#include "bvh/wide_node.h"

namespace rt::bvh {

// A child's sort key: its entry distance's bits (>= +0, so they order as the
// distances do) with the low three replaced by its slot.
[[gnu::always_inline]] inline uint32_t entry_key(float t_entry, uint32_t slot) {
    uint32_t bits;
    __builtin_memcpy(&bits, &t_entry, sizeof bits);
    return (bits & ~7u) | slot;
}

// The entry distance a key keeps: rounded down by at most three bits, so a
// child is never dropped for a hit nearer than where the ray enters it.
[[gnu::always_inline]] inline float entry_distance(uint32_t key) {
    const uint32_t bits = key & ~7u;
    float t;
    __builtin_memcpy(&t, &bits, sizeof t);
    return t;
}

// Per-ray constants: for each axis, which row of a node holds the plane the
// ray enters by (the lower one when it runs towards +axis).
struct WideBoxRay {
    float origin[3];
    float inv_direction[3];
    // inv_direction scaled by kExitScale, for the exit planes: the same
    // roundings as scaling each exit distance, one product fewer per plane.
    float inv_exit[3];
    uint32_t near_row[3];  // offsets in floats from WideNode::lower
    uint32_t far_row[3];

    explicit WideBoxRay(const Ray& ray) {
        constexpr uint32_t kUpper = 3 * kWideWidth;  // WideNode::upper follows lower
        for (int axis = 0; axis < 3; ++axis) {
            origin[axis] = ray.origin[axis];
            inv_direction[axis] = 1.0f / ray.direction[axis];
            inv_exit[axis] = inv_direction[axis] * kExitScale;
            const bool negative = inv_direction[axis] < 0.0f;
            near_row[axis] = uint32_t(axis) * kWideWidth + (negative ? kUpper : 0);
            far_row[axis] = uint32_t(axis) * kWideWidth + (negative ? 0 : kUpper);
        }
    }
};

static_assert(offsetof(WideNode, upper) == 3 * kWideWidth * sizeof(float));

static_assert(offsetof(WideBoxes, upper) == offsetof(WideNode, upper));

// A plane row of four children's boxes; in a moving tree interpolated to the
// ray's time (lerp_position's arithmetic, its difference stored).
template <bool kMoving>
[[gnu::always_inline]] inline __m128 plane_row_sse2(const float* open, const float* motion, uint32_t offset,
                                                    __m128 time) {
    const __m128 at_open = _mm_load_ps(open + offset);
    if constexpr (!kMoving) {
        return at_open;
    } else {
        return _mm_add_ps(at_open, _mm_mul_ps(time, _mm_load_ps(motion + offset)));
    }
}

// SSE2 has no signed 32-bit maximum or minimum: a compare and a select.
[[gnu::always_inline]] inline __m128i max_epi32_sse2(__m128i a, __m128i b) {
    const __m128i a_greater = _mm_cmpgt_epi32(a, b);
    return _mm_or_si128(_mm_and_si128(a_greater, a), _mm_andnot_si128(a_greater, b));
}
[[gnu::always_inline]] inline __m128i min_epi32_sse2(__m128i a, __m128i b) {
    const __m128i a_greater = _mm_cmpgt_epi32(a, b);
    return _mm_or_si128(_mm_and_si128(a_greater, b), _mm_andnot_si128(a_greater, a));
}

// Bit i of the result: the ray enters child i's box before t_max; t_entry[i]
// is then where (at least 0). Lanes that miss leave t_entry meaningless.
// `close` (the node's WideBoxes) and `time` are read only when kMoving.
template <bool kMoving = false>
inline uint32_t wide_box_test_sse2(const WideNode& node, const WideBoxRay& ray, float t_max, float* t_entry,
                                   const WideBoxes* motion = nullptr, float time = 0.0f) {
    const float* rows = node.lower[0];
    const float* motion_rows = kMoving ? motion->lower[0] : nullptr;
    const __m128 time4 = _mm_set1_ps(time);
    const __m128 t_max4 = _mm_set1_ps(t_max);
    uint32_t hits = 0;
    for (uint32_t half = 0; half < kWideWidth; half += 4) {
        __m128i t_near[3], t_far[3];
        for (int axis = 0; axis < 3; ++axis) {
            const __m128 origin = _mm_set1_ps(ray.origin[axis]);
            const __m128 near_plane = plane_row_sse2<kMoving>(rows, motion_rows, ray.near_row[axis] + half, time4);
            const __m128 far_plane = plane_row_sse2<kMoving>(rows, motion_rows, ray.far_row[axis] + half, time4);
            t_near[axis] = _mm_castps_si128(_mm_mul_ps(_mm_sub_ps(near_plane, origin), _mm_set1_ps(ray.inv_direction[axis])));
            // min returns its second operand when either is NaN: t_max.
            t_far[axis] = _mm_castps_si128(
                _mm_min_ps(_mm_mul_ps(_mm_sub_ps(far_plane, origin), _mm_set1_ps(ray.inv_exit[axis])), t_max4));
        }
        const __m128i enter =
            max_epi32_sse2(max_epi32_sse2(t_near[0], t_near[1]), max_epi32_sse2(t_near[2], _mm_setzero_si128()));
        const __m128i exit = min_epi32_sse2(min_epi32_sse2(t_far[0], t_far[1]), t_far[2]);
        // enter <= exit and enter < t_max, as integers: enter and t_max are >= +0.
        const __m128i miss = _mm_or_si128(_mm_cmpgt_epi32(enter, exit),
                                          _mm_cmpgt_epi32(enter, _mm_sub_epi32(_mm_castps_si128(t_max4), _mm_set1_epi32(1))));
        _mm_storeu_ps(t_entry + half, _mm_castsi128_ps(enter));
        hits |= (~uint32_t(_mm_movemask_ps(_mm_castsi128_ps(miss))) & 0xfu) << half;
    }
    return hits;
}

}  // namespace rt::bvh
