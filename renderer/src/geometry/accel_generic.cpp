// The ray query kernels for any x86-64: SSE2 box and triangle tests.
#include "geometry/accel_kernel_headers.h"

// The packet kernels' 32-byte vectors (packet_lanes.inl) live only in
// inlined functions, so GCC's note that SSE2 code passes them otherwise than
// AVX code would, which it gives at the end of the file, concerns no call.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace rt::generic {

struct EntryDistances {
    alignas(16) float t[bvh::kWideWidth];
};

template <bool kMoving>
[[gnu::always_inline]] inline uint32_t wide_box_test(const bvh::WideNode& node, const bvh::WideBoxRay& ray, float t_max,
                                                     EntryDistances& t_entry, const bvh::WideBoxes* motion, float time) {
    return bvh::wide_box_test_sse2<kMoving>(node, ray, t_max, t_entry.t, motion, time);
}

// The keys of the children a ray enters, in slot order.
class HitKeys {
  public:
    HitKeys(const EntryDistances& t_entry, uint32_t hits) : t_entry_(t_entry), hits_(hits) {}
    [[gnu::always_inline]] uint32_t next() {
        const uint32_t slot = uint32_t(__builtin_ctz(hits_));
        hits_ &= hits_ - 1;
        return bvh::entry_key(t_entry_.t[slot], slot);
    }

  private:
    const EntryDistances& t_entry_;
    uint32_t hits_;
};

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
