// The watertight ray/triangle test (triangle.h) on the four triangles of a
// block at once, in SSE2, which every x86-64 has. Lane by lane it performs the
// scalar test's float operations in the same order, and it hands the lanes
// where an edge function is exactly zero to the scalar test, which decides them
// in double: so each lane's verdict, t, u and v equal the scalar test's bit for
// bit, and the watertight guarantee carries over unchanged.
#pragma once

#include <emmintrin.h>

#include <cstdint>

#include "geometry/triangle.h"
#include "geometry/triangle_block.h"

namespace rt {

// Per-ray constants of the shear, broadcast.
struct WatertightRay4 {
    WatertightRay scalar;
    __m128 ox, oy, oz;  // origin along kx, ky, kz
    __m128 sx, sy, sz;

    WatertightRay4() = default;
    explicit WatertightRay4(const WatertightRay& r)
        : scalar(r),
          ox(_mm_set1_ps(r.origin[r.kx])),
          oy(_mm_set1_ps(r.origin[r.ky])),
          oz(_mm_set1_ps(r.origin[r.kz])),
          sx(_mm_set1_ps(r.sx)),
          sy(_mm_set1_ps(r.sy)),
          sz(_mm_set1_ps(r.sz)) {}
};

struct BlockHits {
    alignas(16) float t[4];
    alignas(16) float u[4];
    alignas(16) float v[4];
};

// Two blocks' hits, lane 4 * k + i being lane i of block k.
struct PairHits {
    BlockHits half[2];
    float t(uint32_t lane) const { return half[lane >> 2].t[lane & 3]; }
    float u(uint32_t lane) const { return half[lane >> 2].u[lane & 3]; }
    float v(uint32_t lane) const { return half[lane >> 2].v[lane & 3]; }
};

namespace block_test_detail {

inline __m128 abs4(__m128 x) { return _mm_andnot_ps(_mm_set1_ps(-0.0f), x); }
inline __m128 max3(__m128 x, __m128 y, __m128 z) { return _mm_max_ps(x, _mm_max_ps(y, z)); }

}  // namespace block_test_detail

// Bit i set: lane i is hit with 0 < t < t_max; hits.t/u/v[i] then hold the hit.
// `block` is the triangles as they are at the ray's time.
[[gnu::always_inline]] inline uint32_t intersect_block(const WatertightRay4& r, const TriangleBlock& block, float t_max,
                                                       BlockHits& hits) {
    using namespace block_test_detail;
    const int kx = r.scalar.kx, ky = r.scalar.ky, kz = r.scalar.kz;
    auto row = [&](int vertex, int axis) { return _mm_load_ps(block.v[vertex][axis]); };
    const __m128 a_z = _mm_sub_ps(row(0, kz), r.oz), b_z = _mm_sub_ps(row(1, kz), r.oz), c_z = _mm_sub_ps(row(2, kz), r.oz);
    const __m128 ax = _mm_sub_ps(_mm_sub_ps(row(0, kx), r.ox), _mm_mul_ps(r.sx, a_z));
    const __m128 ay = _mm_sub_ps(_mm_sub_ps(row(0, ky), r.oy), _mm_mul_ps(r.sy, a_z));
    const __m128 bx = _mm_sub_ps(_mm_sub_ps(row(1, kx), r.ox), _mm_mul_ps(r.sx, b_z));
    const __m128 by = _mm_sub_ps(_mm_sub_ps(row(1, ky), r.oy), _mm_mul_ps(r.sy, b_z));
    const __m128 cx = _mm_sub_ps(_mm_sub_ps(row(2, kx), r.ox), _mm_mul_ps(r.sx, c_z));
    const __m128 cy = _mm_sub_ps(_mm_sub_ps(row(2, ky), r.oy), _mm_mul_ps(r.sy, c_z));

    const __m128 e0 = _mm_sub_ps(_mm_mul_ps(cx, by), _mm_mul_ps(cy, bx));
    const __m128 e1 = _mm_sub_ps(_mm_mul_ps(ax, cy), _mm_mul_ps(ay, cx));
    const __m128 e2 = _mm_sub_ps(_mm_mul_ps(bx, ay), _mm_mul_ps(by, ax));

    const __m128 zero = _mm_setzero_ps();
    const __m128i used = _mm_cmpeq_epi32(_mm_load_si128(reinterpret_cast<const __m128i*>(block.prim)),
                                         _mm_set1_epi32(int(TriangleBlock::kEmpty)));
    const uint32_t used_lanes = ~uint32_t(_mm_movemask_ps(_mm_castsi128_ps(used))) & 0xfu;
    const uint32_t exact_zero =
        uint32_t(_mm_movemask_ps(_mm_or_ps(_mm_or_ps(_mm_cmpeq_ps(e0, zero), _mm_cmpeq_ps(e1, zero)), _mm_cmpeq_ps(e2, zero)))) &
        used_lanes;

    // Some edge function below 0 and some above: their sign bits differ
    // (the lanes where one is 0, of either sign, are exact_zero's). Only the
    // sign bits of `reject` and `accept` are read, by movemask.
    __m128 reject = _mm_andnot_ps(_mm_and_ps(_mm_and_ps(e0, e1), e2), _mm_or_ps(_mm_or_ps(e0, e1), e2));
    // Most blocks a ray is tested against miss all four triangles: leave them
    // before det, the division and the error bound.
    const uint32_t candidates = ~uint32_t(_mm_movemask_ps(reject)) & used_lanes & ~exact_zero;
    if ((candidates | exact_zero) == 0) return 0;
    // The candidates' edge functions are nonzero and of one sign: their sum
    // is not 0 (rounding takes it no nearer 0 than its largest term), so the
    // scalar test's det == 0 rejects none of them.
    const __m128 det = _mm_add_ps(_mm_add_ps(e0, e1), e2);

    const __m128 az = _mm_mul_ps(r.sz, a_z), bz = _mm_mul_ps(r.sz, b_z), cz = _mm_mul_ps(r.sz, c_z);
    const __m128 t_scaled = _mm_add_ps(_mm_add_ps(_mm_mul_ps(e0, az), _mm_mul_ps(e1, bz)), _mm_mul_ps(e2, cz));
    const __m128 t_max_det = _mm_mul_ps(_mm_set1_ps(t_max), det);
    // 0 < t_scaled / det < t_max, as t_scaled and t_max * det with det's sign
    // taken off both (det is not 0 where it matters): negation is exact, so
    // these are the scalar test's two cases, bit for bit.
    const __m128 det_sign = _mm_and_ps(det, _mm_set1_ps(-0.0f));
    const __m128 t_unsigned = _mm_xor_ps(t_scaled, det_sign);
    reject = _mm_or_ps(reject, _mm_or_ps(_mm_cmple_ps(t_unsigned, zero),
                                         _mm_cmpgt_ps(t_unsigned, _mm_xor_ps(t_max_det, det_sign))));

    const __m128 inv_det = _mm_div_ps(_mm_set1_ps(1.0f), det);
    const __m128 t = _mm_mul_ps(t_scaled, inv_det);
    __m128 accept = _mm_andnot_ps(reject, _mm_cmplt_ps(t, _mm_set1_ps(t_max)));
    uint32_t hit_lanes = uint32_t(_mm_movemask_ps(accept)) & candidates;
    if ((hit_lanes | exact_zero) == 0) return 0;

    // The conservative bound on t's rounding error (pbrt-v4, section 6.8.6).
    const __m128 max_zt = max3(abs4(az), abs4(bz), abs4(cz));
    const __m128 max_xt = max3(abs4(ax), abs4(bx), abs4(cx));
    const __m128 max_yt = max3(abs4(ay), abs4(by), abs4(cy));
    const __m128 gamma2 = _mm_set1_ps(gamma_bound(2)), gamma3 = _mm_set1_ps(gamma_bound(3)),
                 gamma5 = _mm_set1_ps(gamma_bound(5));
    const __m128 delta_z = _mm_mul_ps(gamma3, max_zt);
    const __m128 delta_x = _mm_mul_ps(gamma5, _mm_add_ps(max_xt, max_zt));
    const __m128 delta_y = _mm_mul_ps(gamma5, _mm_add_ps(max_yt, max_zt));
    const __m128 delta_e = _mm_mul_ps(_mm_set1_ps(2.0f),
                                      _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_mul_ps(gamma2, max_xt), max_yt),
                                                            _mm_mul_ps(delta_y, max_xt)),
                                                 _mm_mul_ps(delta_x, max_yt)));
    const __m128 max_e = max3(abs4(e0), abs4(e1), abs4(e2));
    const __m128 delta_t = _mm_mul_ps(
        _mm_mul_ps(_mm_set1_ps(3.0f), _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_mul_ps(gamma3, max_e), max_zt),
                                                            _mm_mul_ps(delta_e, max_zt)),
                                                 _mm_mul_ps(delta_z, max_e))),
        abs4(inv_det));
    hit_lanes &= uint32_t(_mm_movemask_ps(_mm_cmpnle_ps(t, delta_t)));

    _mm_store_ps(hits.t, t);
    _mm_store_ps(hits.u, _mm_mul_ps(e1, inv_det));
    _mm_store_ps(hits.v, _mm_mul_ps(e2, inv_det));
    // Rare: an edge function of exactly zero, decided in double by the scalar test.
    for (uint32_t lanes = exact_zero; lanes != 0; lanes &= lanes - 1) {
        const uint32_t lane = uint32_t(__builtin_ctz(lanes));
        TriangleHit hit;
        if (!intersect_triangle(r.scalar, block.vertex(lane, 0), block.vertex(lane, 1), block.vertex(lane, 2), t_max, hit))
            continue;
        hits.t[lane] = hit.t, hits.u[lane] = hit.u, hits.v[lane] = hit.v;
        hit_lanes |= 1u << lane;
    }
    return hit_lanes;
}

// The `count` (1 or 2) blocks of `pair` against the same t_max, with the
// four-lane test: what every SIMD path's pair test must answer.
inline uint32_t intersect_block_pair_sse2(const WatertightRay4& r, const TriangleBlock* const* pair, uint32_t count,
                                          float t_max, PairHits& hits) {
    uint32_t lanes = intersect_block(r, *pair[0], t_max, hits.half[0]);
    if (count > 1) lanes |= intersect_block(r, *pair[1], t_max, hits.half[1]) << 4;
    return lanes;
}

// The block as it is at `time`, each vertex moving in a straight line by
// `motion` (close - open, as make_motion_blocks stores it): lerp_position's
// arithmetic, lane by lane, so the vertices equal the scene's at that time.
inline void lerp_block(const TriangleBlock& open, const TriangleBlock& motion, float time, TriangleBlock& out) {
    const __m128 t = _mm_set1_ps(time);
    for (int k = 0; k < 3; ++k)
        for (int axis = 0; axis < 3; ++axis) {
            const __m128 a = _mm_load_ps(open.v[k][axis]);
            const __m128 d = _mm_load_ps(motion.v[k][axis]);
            _mm_store_ps(out.v[k][axis], _mm_add_ps(a, _mm_mul_ps(t, d)));
        }
    _mm_store_si128(reinterpret_cast<__m128i*>(out.prim), _mm_load_si128(reinterpret_cast<const __m128i*>(open.prim)));
}

}  // namespace rt
