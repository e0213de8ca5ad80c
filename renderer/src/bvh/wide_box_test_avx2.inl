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

// The entry distances of a node's eight children, kept in a register.
struct EntryDistances {
    __m256 t;
};

template <bool kMoving>
[[gnu::always_inline]] inline uint32_t wide_box_test(const bvh::WideNode& node, const bvh::WideBoxRay& ray, float t_max,
                                                     EntryDistances& t_entry, const bvh::WideBoxes* motion, float time) {
    const float* rows = node.lower[0];
    const float* motion_rows = kMoving ? motion->lower[0] : nullptr;
    const __m256 time8 = _mm256_set1_ps(time);
    const __m256 t_max8 = _mm256_set1_ps(t_max);
    __m256i t_near[3], t_far[3];
    for (int axis = 0; axis < 3; ++axis) {
        const __m256 origin = _mm256_set1_ps(ray.origin[axis]);
        const __m256 near_plane = plane_row<kMoving>(rows, motion_rows, ray.near_row[axis], time8);
        const __m256 far_plane = plane_row<kMoving>(rows, motion_rows, ray.far_row[axis], time8);
        t_near[axis] =
            _mm256_castps_si256(_mm256_mul_ps(_mm256_sub_ps(near_plane, origin), _mm256_set1_ps(ray.inv_direction[axis])));
        t_far[axis] = _mm256_castps_si256(_mm256_min_ps(
            _mm256_mul_ps(_mm256_sub_ps(far_plane, origin), _mm256_set1_ps(ray.inv_exit[axis])), t_max8));
    }
    // wide_box_test.h says why integers.
    const __m256i enter = _mm256_max_epi32(_mm256_max_epi32(t_near[0], t_near[1]),
                                           _mm256_max_epi32(t_near[2], _mm256_setzero_si256()));
    const __m256i exit = _mm256_min_epi32(_mm256_min_epi32(t_far[0], t_far[1]), t_far[2]);
    const __m256i miss = _mm256_or_si256(
        _mm256_cmpgt_epi32(enter, exit),
        _mm256_cmpgt_epi32(enter, _mm256_sub_epi32(_mm256_castps_si256(t_max8), _mm256_set1_epi32(1))));
    t_entry.t = _mm256_castsi256_ps(enter);
    return ~uint32_t(_mm256_movemask_ps(_mm256_castsi256_ps(miss))) & 0xffu;
}

// The keys (bvh::entry_key) of the children a ray enters, in slot order,
// formed in the register the box test left and taken from it by a permute:
// reading the distances back from memory waits on forwarding a 32-byte store
// to 4-byte loads. (Packing them to the front first, by AVX-512's
// vpcompressd as Embree's traverseClosestHitAVX512VL8 does, ran no faster.)
class HitKeys {
  public:
    HitKeys(const EntryDistances& t_entry, uint32_t hits) : hits_(hits) {
        const __m256i slots = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
        keys_ = _mm256_or_si256(_mm256_and_si256(_mm256_castps_si256(t_entry.t), _mm256_set1_epi32(~7)), slots);
    }
    [[gnu::always_inline]] uint32_t next() {
        const uint32_t slot = uint32_t(__builtin_ctz(hits_));
        hits_ &= hits_ - 1;
        return uint32_t(_mm256_cvtsi256_si32(_mm256_permutevar8x32_epi32(keys_, _mm256_set1_epi32(int(slot)))));
    }

  private:
    __m256i keys_;
    uint32_t hits_;  // the children yet to come
};
