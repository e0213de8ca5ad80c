// Eight float lanes for the packet kernels (packet_setup.inl,
// packet_traverse.inl, geometry/triangle_rays_test.inl), compiled once per
// SIMD path inside its ISA namespace: GCC vector extensions, which are AVX2
// registers in the AVX2 kernels and pairs of SSE2 registers in the generic
// ones, so one text serves both.

typedef float PacketLanes __attribute__((vector_size(32)));
typedef int32_t PacketMask __attribute__((vector_size(32)));

[[gnu::always_inline]] inline PacketLanes lanes_load(const float* p) {
    PacketLanes v;
    __builtin_memcpy(&v, p, sizeof v);
    return v;
}

[[gnu::always_inline]] inline PacketLanes lanes_splat(float x) { return PacketLanes{} + x; }

// Bit i: lane i of a comparison's result is true (all ones). Two SSE
// movemasks, which AVX2 code compiles to a lane extract and two vmovmskps.
[[gnu::always_inline]] inline uint32_t lanes_bits(PacketMask m) {
    __m128 low, high;
    __builtin_memcpy(&low, &m, sizeof low);
    __builtin_memcpy(&high, reinterpret_cast<const char*>(&m) + sizeof low, sizeof high);
    return uint32_t(_mm_movemask_ps(low)) | uint32_t(_mm_movemask_ps(high)) << 4;
}

[[gnu::always_inline]] inline void lanes_store(float* p, PacketLanes v) { __builtin_memcpy(p, &v, sizeof v); }
[[gnu::always_inline]] inline PacketLanes lanes_min(PacketLanes a, PacketLanes b) { return a < b ? a : b; }
[[gnu::always_inline]] inline PacketLanes lanes_max(PacketLanes a, PacketLanes b) { return a > b ? a : b; }

// |x|, lane by lane: the sign bit cleared.
[[gnu::always_inline]] inline PacketLanes lanes_abs(PacketLanes x) {
    PacketMask bits;
    __builtin_memcpy(&bits, &x, sizeof x);
    bits &= 0x7fffffff;
    __builtin_memcpy(&x, &bits, sizeof x);
    return x;
}

// The largest of |x|, |y| and |z|, lane by lane.
[[gnu::always_inline]] inline PacketLanes lanes_abs_max(PacketLanes x, PacketLanes y, PacketLanes z) {
    return lanes_max(lanes_abs(x), lanes_max(lanes_abs(y), lanes_abs(z)));
}

// The smallest and the largest lane.
[[gnu::always_inline]] inline float lanes_low(PacketLanes v) {
    float low = v[0];
    for (int i = 1; i < 8; ++i) low = std::min(low, v[i]);
    return low;
}
[[gnu::always_inline]] inline float lanes_high(PacketLanes v) {
    float high = v[0];
    for (int i = 1; i < 8; ++i) high = std::max(high, v[i]);
    return high;
}
