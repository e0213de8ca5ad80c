// The ray query kernels for any x86-64: SSE2 box and triangle tests.
#include "geometry/accel_kernel_headers.h"

// The packet kernels' 32-byte vectors (packet_lanes.inl) live only in
// inlined functions, so GCC's note that SSE2 code passes them otherwise than
// AVX code would, which it gives at the end of the file, concerns no call.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace rt::generic {

template <bool kMoving>
[[gnu::always_inline]] inline uint32_t wide_box_test(const bvh::WideNode& node, const bvh::WideBoxRay& ray, float t_max,
                                                     float* t_entry, const bvh::WideBoxes* motion, float time) {
    return bvh::wide_box_test_sse2<kMoving>(node, ray, t_max, t_entry, motion, time);
}

[[gnu::always_inline]] inline uint32_t intersect_block_pair(const WatertightRay4& r, const TriangleBlock* const* pair,
                                                           uint32_t count, float t_max, PairHits& hits) {
    return intersect_block_pair_sse2(r, pair, count, t_max, hits);
}

#include "bvh/wide_traverse.inl"
// Which path these kernels are (bvh/packet_lanes.inl sizes its registers by it).
inline constexpr SimdPath kSimdPath = SimdPath::generic;
#include "bvh/packet_lanes.inl"
#include "bvh/packet_setup.inl"
#include "bvh/packet_traverse.inl"
#include "bvh/packet_masked_traverse.inl"
#include "geometry/accel_kernels.inl"

}  // namespace rt::generic
