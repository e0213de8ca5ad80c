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
// This header has the per-ray constants and the SSE2 test, which every x86-64
// runs; wide_box_test_avx2.inl has the one-register AVX2 test.
#pragma once

#include <emmintrin.h>

#include <cstddef>
#include <cstdint>

#include "bvh/box_test.h"
#include "bvh/wide_node.h"

namespace rt::bvh {

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

// Bit i of the result: the ray enters child i's box before t_max; t_entry[i]
// is then where (at least 0). Lanes that miss leave t_entry meaningless.
// `close` (the node's WideBoxes) and `time` are read only when kMoving.
template <bool kMoving = false>
inline uint32_t wide_box_test_sse2(const WideNode& node, const WideBoxRay& ray, float t_max, float* t_entry,
                                   const WideBoxes* motion = nullptr, float time = 0.0f) {
    const float* rows = node.lower[0];
    const float* motion_rows = kMoving ? motion->lower[0] : nullptr;
    const __m128 time4 = _mm_set1_ps(time);
    uint32_t hits = 0;
    for (uint32_t half = 0; half < kWideWidth; half += 4) {
        __m128 enter = _mm_setzero_ps();
        __m128 exit = _mm_set1_ps(t_max);
        for (int axis = 0; axis < 3; ++axis) {
            const __m128 origin = _mm_set1_ps(ray.origin[axis]);
            const __m128 inv = _mm_set1_ps(ray.inv_direction[axis]);
            const __m128 inv_exit = _mm_set1_ps(ray.inv_exit[axis]);
            const __m128 near_plane = plane_row_sse2<kMoving>(rows, motion_rows, ray.near_row[axis] + half, time4);
            const __m128 far_plane = plane_row_sse2<kMoving>(rows, motion_rows, ray.far_row[axis] + half, time4);
            const __m128 t_near = _mm_mul_ps(_mm_sub_ps(near_plane, origin), inv);
            const __m128 t_far = _mm_mul_ps(_mm_sub_ps(far_plane, origin), inv_exit);
            // max/min return their second operand when either is NaN, as the
            // scalar test keeps its running value: NaN narrows nothing.
            enter = _mm_max_ps(t_near, enter);
            exit = _mm_min_ps(t_far, exit);
        }
        const __m128 hit = _mm_and_ps(_mm_cmple_ps(enter, exit), _mm_cmplt_ps(enter, _mm_set1_ps(t_max)));
        _mm_storeu_ps(t_entry + half, enter);
        hits |= uint32_t(_mm_movemask_ps(hit)) << half;
    }
    return hits;
}

}  // namespace rt::bvh
