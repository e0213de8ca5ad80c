// Two triangle blocks in one pass of AVX2 registers: intersect_block's
// operations on eight lanes, block k in lanes 4k to 4k + 3, so each lane's
// answer is the four-lane test's bit for bit. Included only where AVX2 code is
// compiled, inside its ISA namespace (geometry/accel_avx2.cpp).

namespace pair_detail {

[[gnu::always_inline]] inline __m256 row(const TriangleBlock& a, const TriangleBlock& b, int vertex, int axis) {
    return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_load_ps(a.v[vertex][axis])), _mm_load_ps(b.v[vertex][axis]), 1);
}
[[gnu::always_inline]] inline __m256 abs8(__m256 x) { return _mm256_andnot_ps(_mm256_set1_ps(-0.0f), x); }
[[gnu::always_inline]] inline __m256 max3(__m256 x, __m256 y, __m256 z) { return _mm256_max_ps(x, _mm256_max_ps(y, z)); }
[[gnu::always_inline]] inline __m256 lt(__m256 a, __m256 b) { return _mm256_cmp_ps(a, b, _CMP_LT_OQ); }
[[gnu::always_inline]] inline __m256 le(__m256 a, __m256 b) { return _mm256_cmp_ps(a, b, _CMP_LE_OQ); }
[[gnu::always_inline]] inline __m256 eq(__m256 a, __m256 b) { return _mm256_cmp_ps(a, b, _CMP_EQ_OQ); }

}  // namespace pair_detail

[[gnu::always_inline]] inline uint32_t intersect_block_pair(const WatertightRay4& r, const TriangleBlock* const* pair,
                                                           uint32_t count, float t_max, PairHits& hits) {
    using namespace pair_detail;
    if (count < 2) return intersect_block(r, *pair[0], t_max, hits.half[0]);
    const TriangleBlock& a = *pair[0];
    const TriangleBlock& b = *pair[1];
    const int kx = r.scalar.kx, ky = r.scalar.ky, kz = r.scalar.kz;
    const __m256 ox = _mm256_set1_ps(r.scalar.origin[kx]), oy = _mm256_set1_ps(r.scalar.origin[ky]),
                 oz = _mm256_set1_ps(r.scalar.origin[kz]);
    const __m256 sx = _mm256_set1_ps(r.scalar.sx), sy = _mm256_set1_ps(r.scalar.sy), sz = _mm256_set1_ps(r.scalar.sz);

    const __m256 a_z = _mm256_sub_ps(row(a, b, 0, kz), oz), b_z = _mm256_sub_ps(row(a, b, 1, kz), oz),
                 c_z = _mm256_sub_ps(row(a, b, 2, kz), oz);
    const __m256 ax = _mm256_sub_ps(_mm256_sub_ps(row(a, b, 0, kx), ox), _mm256_mul_ps(sx, a_z));
    const __m256 ay = _mm256_sub_ps(_mm256_sub_ps(row(a, b, 0, ky), oy), _mm256_mul_ps(sy, a_z));
    const __m256 bx = _mm256_sub_ps(_mm256_sub_ps(row(a, b, 1, kx), ox), _mm256_mul_ps(sx, b_z));
    const __m256 by = _mm256_sub_ps(_mm256_sub_ps(row(a, b, 1, ky), oy), _mm256_mul_ps(sy, b_z));
    const __m256 cx = _mm256_sub_ps(_mm256_sub_ps(row(a, b, 2, kx), ox), _mm256_mul_ps(sx, c_z));
    const __m256 cy = _mm256_sub_ps(_mm256_sub_ps(row(a, b, 2, ky), oy), _mm256_mul_ps(sy, c_z));

    const __m256 e0 = _mm256_sub_ps(_mm256_mul_ps(cx, by), _mm256_mul_ps(cy, bx));
    const __m256 e1 = _mm256_sub_ps(_mm256_mul_ps(ax, cy), _mm256_mul_ps(ay, cx));
    const __m256 e2 = _mm256_sub_ps(_mm256_mul_ps(bx, ay), _mm256_mul_ps(by, ax));

    const __m256 zero = _mm256_setzero_ps();
    const __m256i prims = _mm256_insertf128_si256(
        _mm256_castsi128_si256(_mm_load_si128(reinterpret_cast<const __m128i*>(a.prim))),
        _mm_load_si128(reinterpret_cast<const __m128i*>(b.prim)), 1);
    const __m256i empty = _mm256_cmpeq_epi32(prims, _mm256_set1_epi32(int(TriangleBlock::kEmpty)));
    const uint32_t used_lanes = ~uint32_t(_mm256_movemask_ps(_mm256_castsi256_ps(empty))) & 0xffu;
    const uint32_t exact_zero =
        uint32_t(_mm256_movemask_ps(_mm256_or_ps(_mm256_or_ps(eq(e0, zero), eq(e1, zero)), eq(e2, zero)))) & used_lanes;

    // The edge functions' signs differ, and det's sign off both sides of the
    // distance range, as the SSE test (intersect_block) takes them.
    __m256 reject =
        _mm256_andnot_ps(_mm256_and_ps(_mm256_and_ps(e0, e1), e2), _mm256_or_ps(_mm256_or_ps(e0, e1), e2));
    const uint32_t candidates = ~uint32_t(_mm256_movemask_ps(reject)) & used_lanes & ~exact_zero;
    if ((candidates | exact_zero) == 0) return 0;
    // Not 0 for any candidate (intersect_block says why).
    const __m256 det = _mm256_add_ps(_mm256_add_ps(e0, e1), e2);

    const __m256 az = _mm256_mul_ps(sz, a_z), bz = _mm256_mul_ps(sz, b_z), cz = _mm256_mul_ps(sz, c_z);
    const __m256 t_scaled =
        _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(e0, az), _mm256_mul_ps(e1, bz)), _mm256_mul_ps(e2, cz));
    const __m256 t_max_det = _mm256_mul_ps(_mm256_set1_ps(t_max), det);
    const __m256 det_sign = _mm256_and_ps(det, _mm256_set1_ps(-0.0f));
    const __m256 t_unsigned = _mm256_xor_ps(t_scaled, det_sign);
    // Ordered compares, as the SSE test's cmple/cmpgt: NaN compares false.
    const __m256 t_max_unsigned = _mm256_xor_ps(t_max_det, det_sign);
    reject = _mm256_or_ps(reject,
                          _mm256_or_ps(le(t_unsigned, zero), _mm256_cmp_ps(t_unsigned, t_max_unsigned, _CMP_GT_OQ)));

    const __m256 inv_det = _mm256_div_ps(_mm256_set1_ps(1.0f), det);
    const __m256 t = _mm256_mul_ps(t_scaled, inv_det);
    const __m256 accept = _mm256_andnot_ps(reject, lt(t, _mm256_set1_ps(t_max)));
    uint32_t hit_lanes = uint32_t(_mm256_movemask_ps(accept)) & candidates;
    if ((hit_lanes | exact_zero) == 0) return 0;

    const __m256 max_zt = max3(abs8(az), abs8(bz), abs8(cz));
    const __m256 max_xt = max3(abs8(ax), abs8(bx), abs8(cx));
    const __m256 max_yt = max3(abs8(ay), abs8(by), abs8(cy));
    const __m256 gamma2 = _mm256_set1_ps(gamma_bound(2)), gamma3 = _mm256_set1_ps(gamma_bound(3)),
                 gamma5 = _mm256_set1_ps(gamma_bound(5));
    const __m256 delta_z = _mm256_mul_ps(gamma3, max_zt);
    const __m256 delta_x = _mm256_mul_ps(gamma5, _mm256_add_ps(max_xt, max_zt));
    const __m256 delta_y = _mm256_mul_ps(gamma5, _mm256_add_ps(max_yt, max_zt));
    const __m256 delta_e = _mm256_mul_ps(
        _mm256_set1_ps(2.0f), _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(_mm256_mul_ps(gamma2, max_xt), max_yt),
                                                          _mm256_mul_ps(delta_y, max_xt)),
                                            _mm256_mul_ps(delta_x, max_yt)));
    const __m256 max_e = max3(abs8(e0), abs8(e1), abs8(e2));
    const __m256 delta_t = _mm256_mul_ps(
        _mm256_mul_ps(_mm256_set1_ps(3.0f),
                      _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(_mm256_mul_ps(gamma3, max_e), max_zt),
                                                  _mm256_mul_ps(delta_e, max_zt)),
                                    _mm256_mul_ps(delta_z, max_e))),
        abs8(inv_det));
    hit_lanes &= uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(t, delta_t, _CMP_NLE_UQ)));

    const __m256 u = _mm256_mul_ps(e1, inv_det), v = _mm256_mul_ps(e2, inv_det);
    _mm_store_ps(hits.half[0].t, _mm256_castps256_ps128(t));
    _mm_store_ps(hits.half[1].t, _mm256_extractf128_ps(t, 1));
    _mm_store_ps(hits.half[0].u, _mm256_castps256_ps128(u));
    _mm_store_ps(hits.half[1].u, _mm256_extractf128_ps(u, 1));
    _mm_store_ps(hits.half[0].v, _mm256_castps256_ps128(v));
    _mm_store_ps(hits.half[1].v, _mm256_extractf128_ps(v, 1));
    for (uint32_t lanes = exact_zero; lanes != 0; lanes &= lanes - 1) {
        const uint32_t lane = uint32_t(__builtin_ctz(lanes));
        const TriangleBlock& block = *pair[lane >> 2];
        const uint32_t l = lane & 3;
        TriangleHit hit;
        if (!intersect_triangle(r.scalar, block.vertex(l, 0), block.vertex(l, 1), block.vertex(l, 2), t_max, hit))
            continue;
        BlockHits& half = hits.half[lane >> 2];
        half.t[l] = hit.t, half.u[l] = hit.u, half.v[l] = hit.v;
        hit_lanes |= 1u << lane;
    }
    return hit_lanes;
}
