// What the binned SAH builder sorts: compact copies of the primitives' boxes.
#pragma once

#include <emmintrin.h>

#include <bit>
#include <cstdint>
#include <span>
#include <type_traits>

#include "bvh/sah_bins.h"
#include "util/bounds.h"
#include "util/math.h"

namespace rt::bvh::detail {

// The builder's copy of a primitive: its box, in SSE-loadable halves, and its
// number; the builder reorders these rather than numbers into the caller's
// arrays, so that binning and partitioning stream through memory. When every
// centroid is its box's centre, as the accelerator's are, 32 bytes hold all
// (CenteredRef); else the centroid comes along (StoredCentroidRef).
struct alignas(32) CenteredRef {
    float lower[3];
    uint32_t id;
    float upper[3];
    uint32_t unused;

    __m128 lower4() const { return _mm_load_ps(lower); }
    __m128 upper4() const { return _mm_load_ps(upper); }
    // As Bounds3::center computes it, so that the bins are the same. Lane 3
    // is cleared first: as a float the id is denormal, whose arithmetic takes
    // a slow microcode path (the build ran 2.5 times slower).
    __m128 centroid4() const {
        const __m128 xyz = _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0));
        return _mm_mul_ps(_mm_add_ps(_mm_and_ps(lower4(), xyz), upper4()), _mm_set1_ps(0.5f));
    }
    float centroid(int axis) const { return 0.5f * (lower[axis] + upper[axis]); }
};

struct alignas(16) StoredCentroidRef {
    float lower[3];
    uint32_t id;
    float upper[3];
    uint32_t unused;
    float center[4];

    __m128 lower4() const { return _mm_load_ps(lower); }
    __m128 upper4() const { return _mm_load_ps(upper); }
    __m128 centroid4() const { return _mm_load_ps(center); }
    float centroid(int axis) const { return center[axis]; }
};

static_assert(sizeof(CenteredRef) == 32 && sizeof(StoredCentroidRef) == 48);

inline bool same_float(float a, float b) { return std::bit_cast<uint32_t>(a) == std::bit_cast<uint32_t>(b); }

// Fills the references for primitives [begin, end), with their bounds and
// centroid bounds; returns false if some centroid is not its box's centre (then
// CenteredRef cannot stand for it).
template <typename Ref>
bool fill_refs(Ref* refs, std::span<const Bounds3> prim_bounds, std::span<const vec3> centroids, uint32_t begin,
               uint32_t end, Box4& bounds, Box4& centroid_bounds) {
    bool centered = true;
    for (uint32_t i = begin; i < end; ++i) {
        const Bounds3& b = prim_bounds[i];
        const vec3 c = centroids[i];
        Ref& ref = refs[i];
        ref.lower[0] = b.min.x, ref.lower[1] = b.min.y, ref.lower[2] = b.min.z;
        ref.upper[0] = b.max.x, ref.upper[1] = b.max.y, ref.upper[2] = b.max.z;
        ref.id = i;
        ref.unused = 0;
        if constexpr (std::is_same_v<Ref, StoredCentroidRef>) {
            ref.center[0] = c.x, ref.center[1] = c.y, ref.center[2] = c.z, ref.center[3] = 0.0f;
        } else {
            const vec3 center = b.center();
            centered = centered && same_float(c.x, center.x) && same_float(c.y, center.y) && same_float(c.z, center.z);
        }
        bounds.extend(ref.lower4(), ref.upper4());
        centroid_bounds.extend(ref.centroid4());
    }
    return centered;
}

}  // namespace rt::bvh::detail
