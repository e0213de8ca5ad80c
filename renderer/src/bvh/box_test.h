// Ray/box slab test. The exit distances are scaled up by their rounding error
// bound (pbrt-v4, "Bounds3::IntersectP"): without that a ray grazing a box could
// be culled by rounding, and rays through the edges of triangles whose boxes
// only touch would leak past a watertight triangle test.
#pragma once

#include <cstdint>

#if defined(__AVX2__)
#include <immintrin.h>
#endif

#include "bvh/node.h"
#include "util/ray.h"

namespace rt::bvh {

// (plane - origin) * inv_direction rounds three times, the reciprocal included,
// so a computed distance is within gamma_bound(3) of the exact one, relative to
// its size. Exit distances raised by twice that never fall below an entry
// distance they truly exceed.
inline constexpr float kExitScale = 1.0f + 2.0f * gamma_bound(3);

// Per-ray constants of the box test, computed once per ray.
struct BoxRay {
    vec3 origin;
    vec3 inv_direction;
    bool negative[3];  // the ray runs towards -axis, so it enters at the max plane
#if defined(__AVX2__)
    __m256 origin8;         // x y z x | x y z x
    __m256 inv_direction8;  // likewise
    __m256i near_planes;    // lane index of each axis' entry plane within a node
    __m256i far_planes;
#endif

    explicit BoxRay(const Ray& ray) : origin(ray.origin), inv_direction(1.0f / ray.direction) {
        for (int axis = 0; axis < 3; ++axis) negative[axis] = inv_direction[axis] < 0.0f;
#if defined(__AVX2__)
        origin8 = _mm256_setr_ps(origin.x, origin.y, origin.z, origin.x, origin.x, origin.y, origin.z, origin.x);
        inv_direction8 = _mm256_setr_ps(inv_direction.x, inv_direction.y, inv_direction.z, inv_direction.x,
                                        inv_direction.x, inv_direction.y, inv_direction.z, inv_direction.x);
        // A node loads as min x y z, first, max x y z, count; lane 3 repeats x so
        // that the integer fields never enter the arithmetic.
        const int nx = negative[0] ? 4 : 0, ny = negative[1] ? 5 : 1, nz = negative[2] ? 6 : 2;
        near_planes = _mm256_setr_epi32(nx, ny, nz, nx, nx, ny, nz, nx);
        far_planes = _mm256_setr_epi32(nx ^ 4, ny ^ 4, nz ^ 4, nx ^ 4, nx ^ 4, ny ^ 4, nz ^ 4, nx ^ 4);
#endif
    }
};

// Distance at which the ray enters the node's box, at least 0, or kInfinity
// when it misses the box or enters it no earlier than t_max.
inline float entry_distance(const Node& node, const BoxRay& ray, float t_max) {
    float t_enter = 0.0f;
    float t_exit = t_max;
    for (int axis = 0; axis < 3; ++axis) {
        const float t_min_plane = (node.bounds_min[axis] - ray.origin[axis]) * ray.inv_direction[axis];
        const float t_max_plane = (node.bounds_max[axis] - ray.origin[axis]) * ray.inv_direction[axis];
        const float t_near = ray.negative[axis] ? t_max_plane : t_min_plane;
        const float t_far = (ray.negative[axis] ? t_min_plane : t_max_plane) * kExitScale;
        // NaN, from a ray lying in a face's plane, compares false: it narrows nothing.
        t_enter = t_near > t_enter ? t_near : t_enter;
        t_exit = t_far < t_exit ? t_far : t_exit;
    }
    return t_enter <= t_exit && t_enter < t_max ? t_enter : kInfinity;
}

// Bits of ChildEntries::hits, placed where the AVX2 test's sign mask has them.
inline constexpr uint32_t kHitLeft = 0x01;
inline constexpr uint32_t kHitRight = 0x10;

// What the ray does with the boxes of two adjacent nodes. An entry distance
// means something only where its box is hit.
struct ChildEntries {
    float left;
    float right;
    uint32_t hits;  // kHitLeft | kHitRight
};

inline ChildEntries child_entry_distances_scalar(const Node* children, const BoxRay& ray, float t_max) {
    const float left = entry_distance(children[0], ray, t_max);
    const float right = entry_distance(children[1], ray, t_max);
    return {left, right, (left < t_max ? kHitLeft : 0u) | (right < t_max ? kHitRight : 0u)};
}

#if defined(__AVX2__)
// Both boxes at once, in one lane half each; the same operations as
// entry_distance, so the same hits and entry distances bit for bit.
inline ChildEntries child_entry_distances_avx2(const Node* children, const BoxRay& ray, float t_max) {
    const __m256 left = _mm256_load_ps(children[0].bounds_min);
    const __m256 right = _mm256_load_ps(children[1].bounds_min);
    const __m256 near_planes = _mm256_blend_ps(_mm256_permutevar8x32_ps(left, ray.near_planes),
                                               _mm256_permutevar8x32_ps(right, ray.near_planes), 0xf0);
    const __m256 far_planes = _mm256_blend_ps(_mm256_permutevar8x32_ps(left, ray.far_planes),
                                              _mm256_permutevar8x32_ps(right, ray.far_planes), 0xf0);
    const __m256 t_max8 = _mm256_set1_ps(t_max);
    __m256 t_near = _mm256_mul_ps(_mm256_sub_ps(near_planes, ray.origin8), ray.inv_direction8);
    __m256 t_far = _mm256_mul_ps(_mm256_mul_ps(_mm256_sub_ps(far_planes, ray.origin8), ray.inv_direction8),
                                 _mm256_set1_ps(kExitScale));
    // max/min return their second operand when either is NaN: NaN narrows nothing.
    t_near = _mm256_max_ps(t_near, _mm256_setzero_ps());
    t_far = _mm256_min_ps(t_far, t_max8);
    t_near = _mm256_max_ps(t_near, _mm256_permute_ps(t_near, 0b10110001));
    t_near = _mm256_max_ps(t_near, _mm256_permute_ps(t_near, 0b01001110));
    t_far = _mm256_min_ps(t_far, _mm256_permute_ps(t_far, 0b10110001));
    t_far = _mm256_min_ps(t_far, _mm256_permute_ps(t_far, 0b01001110));
    const __m256 hit = _mm256_and_ps(_mm256_cmp_ps(t_near, t_far, _CMP_LE_OQ), _mm256_cmp_ps(t_near, t_max8, _CMP_LT_OQ));
    // The hit flags come from the mask: branching on it is quicker than on the
    // extracted distances.
    return {_mm256_cvtss_f32(t_near), _mm_cvtss_f32(_mm256_extractf128_ps(t_near, 1)),
            uint32_t(_mm256_movemask_ps(hit)) & (kHitLeft | kHitRight)};
}
#endif

inline ChildEntries child_entry_distances(const Node* children, const BoxRay& ray, float t_max) {
#if defined(__AVX2__)
    return child_entry_distances_avx2(children, ray, t_max);
#else
    return child_entry_distances_scalar(children, ray, t_max);
#endif
}

}  // namespace rt::bvh
