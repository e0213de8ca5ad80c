// The eight boxes in one AVX2 register per plane row; the operations of
// wide_box_test_sse2. Included only where AVX2 code is compiled (a TU under
// `#pragma GCC target("avx2,...")`, inside its ISA namespace).

template <bool kMoving>
[[gnu::always_inline]] inline __m256 plane_row(const float* open, const float* motion, uint32_t offset, __m256 time) {
    const __m256 at_open = _mm256_load_ps(open + offset);
    if constexpr (!kMoving) {
        return at_open;
    } else {
        return _mm256_add_ps(at_open, _mm256_mul_ps(time, _mm256_load_ps(motion + offset)));
    }
}

template <bool kMoving>
[[gnu::always_inline]] inline uint32_t wide_box_test(const bvh::WideNode& node, const bvh::WideBoxRay& ray, float t_max,
                                                     float* t_entry, const bvh::WideBoxes* motion, float time) {
    const float* rows = node.lower[0];
    const float* motion_rows = kMoving ? motion->lower[0] : nullptr;
    const __m256 time8 = _mm256_set1_ps(time);
    __m256 enter = _mm256_setzero_ps();
    __m256 exit = _mm256_set1_ps(t_max);
    for (int axis = 0; axis < 3; ++axis) {
        const __m256 origin = _mm256_set1_ps(ray.origin[axis]);
        const __m256 inv = _mm256_set1_ps(ray.inv_direction[axis]);
        const __m256 near_plane = plane_row<kMoving>(rows, motion_rows, ray.near_row[axis], time8);
        const __m256 far_plane = plane_row<kMoving>(rows, motion_rows, ray.far_row[axis], time8);
        const __m256 t_near = _mm256_mul_ps(_mm256_sub_ps(near_plane, origin), inv);
        const __m256 t_far = _mm256_mul_ps(_mm256_sub_ps(far_plane, origin), _mm256_set1_ps(ray.inv_exit[axis]));
        enter = _mm256_max_ps(t_near, enter);
        exit = _mm256_min_ps(t_far, exit);
    }
    const __m256 hit = _mm256_and_ps(_mm256_cmp_ps(enter, exit, _CMP_LE_OQ),
                                     _mm256_cmp_ps(enter, _mm256_set1_ps(t_max), _CMP_LT_OQ));
    _mm256_storeu_ps(t_entry, enter);
    return uint32_t(_mm256_movemask_ps(hit));
}
