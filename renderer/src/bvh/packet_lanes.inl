// Float lanes for the packet kernels (packet_setup.inl, packet_traverse.inl,
// packet_masked_traverse.inl, geometry/triangle_rays_test.inl), compiled once per SIMD
// path inside its ISA namespace: GCC vector extensions, so one text serves
// every path.
//
// Two widths: NodeLanes hold one number per child slot of a wide node (8);
// RayLanes one per ray of a packet, as many as a register holds: 16 in the
// AVX-512 kernels (one ZMM register, as Embree's 16-ray packets), 8 in the
// AVX2 ones (one YMM) and in the generic ones (a pair of SSE2 registers).
// The including file sets kSimdPath: GCC's target pragma does not define
// __AVX512F__ and the like in C++.

inline constexpr uint32_t kRayLanes = kSimdPath == SimdPath::avx512 ? 16 : 8;
// Every lane of a RayLanes comparison.
inline constexpr uint32_t kRayLaneBits = uint32_t((uint64_t(1) << kRayLanes) - 1);
static_assert(bvh::kPacketSize % kRayLanes == 0);

typedef float NodeLanes __attribute__((vector_size(4 * bvh::kWideWidth)));
typedef int32_t NodeMask __attribute__((vector_size(4 * bvh::kWideWidth)));
typedef float RayLanes __attribute__((vector_size(4 * kRayLanes)));
typedef int32_t RayMask __attribute__((vector_size(4 * kRayLanes)));
typedef uint32_t RayUints __attribute__((vector_size(4 * kRayLanes)));

// Vectors of a size a template computes: a typedef inside a class template,
// as GCC does not give a function template's local typedef a dependent
// vector_size.
template <uint32_t kBytes>
struct IntsOfSize {
    typedef int32_t type __attribute__((vector_size(kBytes)));
};

template <typename Lanes>
[[gnu::always_inline]] inline Lanes lanes_load(const void* p) {
    Lanes v;
    __builtin_memcpy(&v, p, sizeof v);
    return v;
}

// The same bits as other lanes of the same size.
template <typename To, typename From>
[[gnu::always_inline]] inline To lanes_bitcast(From v) {
    static_assert(sizeof(To) == sizeof(From));
    To to;
    __builtin_memcpy(&to, &v, sizeof to);
    return to;
}

// x in every lane: x - 0 is x, -0 and NaN included, so the compiler makes
// it one broadcast; Lanes{} + x added 0 first (as -0 + 0 is +0, that
// addition stays), a scalar add before every broadcast of the packet and
// triangle tests. 1T against Embree-16, camera packets on the Cornell box
// 0.94 -> 0.98, the teapot's soft shadows 0.88 -> 0.95, the rest 3-5%.
template <typename Lanes>
[[gnu::always_inline]] inline Lanes lanes_splat(float x) {
    return x - Lanes{};
}

// Bit i: lane i of a comparison's result is true (all ones): the lanes' sign
// bits, 128 bits at a time (SSE2 movemask), or with AVX-512 into a mask
// register at once, where the comparison that made them put them anyway.
template <typename Mask>
[[gnu::always_inline]] inline uint32_t lanes_bits(Mask m) {
    if constexpr (kSimdPath == SimdPath::avx512 && sizeof(Mask) == 64) {
        __m512i bits;
        __builtin_memcpy(&bits, &m, sizeof bits);
        return uint32_t(_mm512_movepi32_mask(bits));
    } else if constexpr (kSimdPath == SimdPath::avx512 && sizeof(Mask) == 32) {
        __m256i bits;
        __builtin_memcpy(&bits, &m, sizeof bits);
        return uint32_t(_mm256_movepi32_mask(bits));
    }
    uint32_t bits = 0;
    for (uint32_t quarter = 0; quarter < sizeof(Mask) / 16; ++quarter) {
        __m128 part;
        __builtin_memcpy(&part, reinterpret_cast<const char*>(&m) + 16 * quarter, sizeof part);
        bits |= uint32_t(_mm_movemask_ps(part)) << (4 * quarter);
    }
    return bits;
}

// Bit i: enter[i] <= exit[i] and enter[i] < limit[i], a box test's verdict.
// With AVX-512 the two comparisons go straight into mask registers: through
// lanes_bits, GCC turned the first mask into a vector and back.
template <typename Lanes>
[[gnu::always_inline]] inline uint32_t lanes_entered(Lanes enter, Lanes exit, Lanes limit) {
    if constexpr (kSimdPath == SimdPath::avx512 && sizeof(Lanes) == 64) {
        __m512 e, x, l;
        __builtin_memcpy(&e, &enter, sizeof e), __builtin_memcpy(&x, &exit, sizeof x);
        __builtin_memcpy(&l, &limit, sizeof l);
        return uint32_t(_mm512_mask_cmp_ps_mask(_mm512_cmp_ps_mask(e, x, _CMP_LE_OQ), e, l, _CMP_LT_OQ));
    } else if constexpr (kSimdPath == SimdPath::avx512 && sizeof(Lanes) == 32) {
        __m256 e, x, l;
        __builtin_memcpy(&e, &enter, sizeof e), __builtin_memcpy(&x, &exit, sizeof x);
        __builtin_memcpy(&l, &limit, sizeof l);
        return uint32_t(_mm256_mask_cmp_ps_mask(_mm256_cmp_ps_mask(e, x, _CMP_LE_OQ), e, l, _CMP_LT_OQ));
    } else {
        return lanes_bits((enter <= exit) & (enter < limit));
    }
}

// A comparison of RayLanes, lane by lane, in the form its path combines
// fastest: with AVX-512 the bits of a mask register, where the comparison
// writes them and and/or/not cost no conversion (as vectors, GCC moved each
// combined mask into a vector and back, vpmovm2d / vpmovd2m, in the packet
// triangle test's critical chain); otherwise the lanes, made bits once at
// the end by lane_bits. Every predicate is ordered: NaN compares false.
template <int kPredicate, typename Lanes>
[[gnu::always_inline]] inline auto compare_lanes(Lanes a, Lanes b) {
    if constexpr (kSimdPath == SimdPath::avx512 && sizeof(Lanes) == 64) {
        __m512 x, y;
        __builtin_memcpy(&x, &a, sizeof x), __builtin_memcpy(&y, &b, sizeof y);
        return uint32_t(_mm512_cmp_ps_mask(x, y, kPredicate));
    } else if constexpr (kPredicate == _CMP_LT_OQ) {
        return a < b;
    } else if constexpr (kPredicate == _CMP_LE_OQ) {
        return a <= b;
    } else if constexpr (kPredicate == _CMP_EQ_OQ) {
        return a == b;
    } else {
        static_assert(kPredicate == _CMP_GT_OQ);
        return a > b;
    }
}
using LaneBits = decltype(compare_lanes<_CMP_LT_OQ>(RayLanes{}, RayLanes{}));

[[gnu::always_inline]] inline LaneBits lanes_lt(RayLanes a, RayLanes b) { return compare_lanes<_CMP_LT_OQ>(a, b); }
[[gnu::always_inline]] inline LaneBits lanes_le(RayLanes a, RayLanes b) { return compare_lanes<_CMP_LE_OQ>(a, b); }
[[gnu::always_inline]] inline LaneBits lanes_eq(RayLanes a, RayLanes b) { return compare_lanes<_CMP_EQ_OQ>(a, b); }
[[gnu::always_inline]] inline LaneBits lanes_gt(RayLanes a, RayLanes b) { return compare_lanes<_CMP_GT_OQ>(a, b); }

// The lanes of `m` whose sign bit is set, as compare_lanes gives its verdicts.
template <typename Mask>
[[gnu::always_inline]] inline LaneBits lanes_sign_bits(Mask m) {
    if constexpr (std::is_same_v<LaneBits, uint32_t>) {
        return lanes_bits(m);
    } else {
        return m < 0;
    }
}

// Bit i: lane i of `bits` (compare_lanes' verdicts) is true.
template <typename Bits>
[[gnu::always_inline]] inline uint32_t lane_bits(Bits bits) {
    if constexpr (std::is_same_v<Bits, uint32_t>) {
        return bits;
    } else {
        return lanes_bits(bits);
    }
}

// Lane i all ones where bit i of `bits` is set: lanes_bits' inverse.
[[gnu::always_inline]] inline RayMask lanes_from_bits(uint32_t bits) {
    RayMask lane_bit;
    for (uint32_t i = 0; i < kRayLanes; ++i) lane_bit[i] = int32_t(1u << i);
    return ((RayMask{} + int32_t(bits)) & lane_bit) != 0;
}

template <typename Lanes>
[[gnu::always_inline]] inline void lanes_store(void* p, Lanes v) {
    __builtin_memcpy(p, &v, sizeof v);
}
template <typename Lanes>
[[gnu::always_inline]] inline Lanes lanes_min(Lanes a, Lanes b) {
    return a < b ? a : b;
}
template <typename Lanes>
[[gnu::always_inline]] inline Lanes lanes_max(Lanes a, Lanes b) {
    return a > b ? a : b;
}

// A box's entry and exit distances from its three slabs' (wide_box_test.h
// says why as integers): the entry max(near..., +0), where a negative or NaN
// distance gives way to +0; the exit min(far..., limit), each far distance
// first held to `limit` by a float minimum, which a NaN gives way to.
template <typename Lanes>
[[gnu::always_inline]] inline Lanes slab_entry(const Lanes (&t_near)[3]) {
    using Ints = typename IntsOfSize<sizeof(Lanes)>::type;
    const Ints x = lanes_bitcast<Ints>(t_near[0]), y = lanes_bitcast<Ints>(t_near[1]),
               z = lanes_bitcast<Ints>(t_near[2]);
    const Ints xy = x > y ? x : y, z0 = z > 0 ? z : Ints{};
    return lanes_bitcast<Lanes>(xy > z0 ? xy : z0);
}
template <typename Lanes>
[[gnu::always_inline]] inline Lanes slab_exit(const Lanes (&t_far)[3], Lanes limit) {
    using Ints = typename IntsOfSize<sizeof(Lanes)>::type;
    const Ints x = lanes_bitcast<Ints>(t_far[0] < limit ? t_far[0] : limit),
               y = lanes_bitcast<Ints>(t_far[1] < limit ? t_far[1] : limit),
               z = lanes_bitcast<Ints>(t_far[2] < limit ? t_far[2] : limit);
    const Ints xy = x < y ? x : y;
    return lanes_bitcast<Lanes>(xy < z ? xy : z);
}

// |x|, lane by lane: the sign bit cleared.
template <typename Lanes>
[[gnu::always_inline]] inline Lanes lanes_abs(Lanes x) {
    typename IntsOfSize<sizeof(Lanes)>::type bits;
    static_assert(sizeof bits == sizeof x);
    __builtin_memcpy(&bits, &x, sizeof x);
    bits &= 0x7fffffff;
    __builtin_memcpy(&x, &bits, sizeof x);
    return x;
}

// The largest of |x|, |y| and |z|, lane by lane.
template <typename Lanes>
[[gnu::always_inline]] inline Lanes lanes_abs_max(Lanes x, Lanes y, Lanes z) {
    return lanes_max(lanes_abs(x), lanes_max(lanes_abs(y), lanes_abs(z)));
}

// A vector's lower and upper halves, taken in registers: copied out through
// memory (memcpy of the halves), each reduction step stored a whole
// register and reloaded half of it (camera packets ran 2-3% slower).
template <size_t kFirst, typename Lanes, size_t... I>
[[gnu::always_inline]] inline auto lanes_half(Lanes v, std::index_sequence<I...>) {
    return __builtin_shufflevector(v, v, (kFirst + I)...);
}
template <typename Lanes>
[[gnu::always_inline]] inline auto lanes_lower_half(Lanes v) {
    return lanes_half<0>(v, std::make_index_sequence<sizeof(Lanes) / sizeof(float) / 2>{});
}
template <typename Lanes>
[[gnu::always_inline]] inline auto lanes_upper_half(Lanes v) {
    constexpr size_t kHalf = sizeof(Lanes) / sizeof(float) / 2;
    return lanes_half<kHalf>(v, std::make_index_sequence<kHalf>{});
}

// The smallest, the largest lane and their sum: halves folded onto each other, so
// log2(lanes) steps.
template <typename Lanes>
[[gnu::always_inline]] inline float lanes_low(Lanes v) {
    if constexpr (sizeof(Lanes) == sizeof(float)) {
        return v[0];
    } else {
        return lanes_low(lanes_min(lanes_lower_half(v), lanes_upper_half(v)));
    }
}
template <typename Lanes>
[[gnu::always_inline]] inline float lanes_high(Lanes v) {
    if constexpr (sizeof(Lanes) == sizeof(float)) {
        return v[0];
    } else {
        return lanes_high(lanes_max(lanes_lower_half(v), lanes_upper_half(v)));
    }
}
template <typename Lanes>
[[gnu::always_inline]] inline float lanes_sum(Lanes v) {
    if constexpr (sizeof(Lanes) == sizeof(float)) {
        return v[0];
    } else {
        return lanes_sum(lanes_lower_half(v) + lanes_upper_half(v));
    }
}
