// Bins of centroids along the three axes, for the binned SAH builder
// (binned_sah_builder.h): boxes in SSE registers, the centroid-to-bin
// mapping, and the split between bins.
#pragma once

#include <emmintrin.h>  // SSE2, which every x86-64 CPU has

#include <bit>
#include <cstdint>
#include <cstring>

#include "util/bounds.h"
#include "util/math.h"

namespace rt::bvh::detail {

constexpr uint32_t kMaxBins = 32;

// An axis-aligned box in SSE registers; lane 3 means nothing. Min and max
// take the new value first, as glm::min and glm::max do, so that a NaN
// coordinate never enters a box, here or in Bounds3::extend.
struct Box4 {
    __m128 lower = _mm_set1_ps(kInfinity);
    __m128 upper = _mm_set1_ps(-kInfinity);

    void extend(__m128 point) {
        lower = _mm_min_ps(point, lower);
        upper = _mm_max_ps(point, upper);
    }
    void extend(__m128 other_lower, __m128 other_upper) {
        lower = _mm_min_ps(other_lower, lower);
        upper = _mm_max_ps(other_upper, upper);
    }
    void extend(const Box4& other) { extend(other.lower, other.upper); }

    Bounds3 bounds() const {
        alignas(16) float l[4], u[4];
        _mm_store_ps(l, lower);
        _mm_store_ps(u, upper);
        return {vec3(l[0], l[1], l[2]), vec3(u[0], u[1], u[2])};
    }

    // Bounds3::surface_area, the same operations in the same order. Lane 3
    // of `lower` is cleared first: it may hold primitive numbers (see
    // CenteredRef).
    float surface_area() const {
        if (_mm_movemask_ps(_mm_cmpgt_ps(lower, upper)) & 0x7) return 0.0f;
        const __m128 xyz = _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0));
        const __m128 e = _mm_sub_ps(upper, _mm_and_ps(lower, xyz));  // upper's lane 3 is 0
        // x y, y z, z x
        const __m128 products = _mm_mul_ps(e, _mm_shuffle_ps(e, e, _MM_SHUFFLE(3, 0, 2, 1)));
        const __m128 sum = _mm_add_ss(_mm_add_ss(products, _mm_shuffle_ps(products, products, 1)),
                                      _mm_shuffle_ps(products, products, 2));
        return 2.0f * _mm_cvtss_f32(sum);
    }
};

// Maps centroids to bins along each axis of a node's centroid bounds.
struct BinMapping {
    vec3 origin;
    vec3 scale;  // bins per unit length; 0 on axes that cannot be split
    uint32_t bin_count;
    __m128 origin4;
    __m128 scale4;
    __m128 last_bin4;

    BinMapping(const Bounds3& centroid_bounds, uint32_t bins) : origin(centroid_bounds.min), bin_count(bins) {
        const vec3 extent = centroid_bounds.extent();
        for (int axis = 0; axis < 3; ++axis) {
            const float s = float(bins) / extent[axis];
            scale[axis] = extent[axis] > 0.0f && std::isfinite(s) ? s : 0.0f;
        }
        origin4 = _mm_setr_ps(origin.x, origin.y, origin.z, 0.0f);
        scale4 = _mm_setr_ps(scale.x, scale.y, scale.z, 0.0f);
        last_bin4 = _mm_set1_ps(float(bins - 1));
    }

    bool splittable(int axis) const { return scale[axis] > 0.0f; }

    // The bin of a centroid along each axis: (centroid - origin) * scale,
    // rounded down into [0, bin_count). A NaN centroid lands in bin 0.
    __m128i bins(__m128 centroid) const {
        __m128 position = _mm_mul_ps(_mm_sub_ps(centroid, origin4), scale4);
        position = _mm_max_ps(position, _mm_setzero_ps());  // NaN -> 0
        return _mm_cvttps_epi32(_mm_min_ps(position, last_bin4));
    }

    // Whether a centroid's bin along `axis` is below `bin`: the same position
    // as bins() computes, compared before rounding (for an integer `bin`
    // floor(p) < bin exactly when p < bin); NaN is below.
    bool below(float centroid, int axis, float bin) const {
        const float position = (centroid - origin[axis]) * scale[axis];
        return !(position >= bin);
    }
};

// Bins of one node along all three axes. Trivially constructed; reset once,
// then cleared after each use, which touches only the bins that were used.
struct BinSet {
    struct Bin {
        __m128 lower;
        __m128 upper;
    };
    Bin bin[3][kMaxBins];
    uint32_t count[3][kMaxBins];

    void reset() {
        const __m128 inf = _mm_set1_ps(kInfinity), minus_inf = _mm_set1_ps(-kInfinity);
        for (int axis = 0; axis < 3; ++axis) {
            for (uint32_t b = 0; b < kMaxBins; ++b) {
                bin[axis][b].lower = inf;
                bin[axis][b].upper = minus_inf;
            }
            std::memset(count[axis], 0, sizeof(count[axis]));
        }
    }

    void merge(const BinSet& other, uint32_t bin_count) {
        for (int axis = 0; axis < 3; ++axis) {
            for (uint32_t b = 0; b < bin_count; ++b) {
                bin[axis][b].lower = _mm_min_ps(other.bin[axis][b].lower, bin[axis][b].lower);
                bin[axis][b].upper = _mm_max_ps(other.bin[axis][b].upper, bin[axis][b].upper);
                count[axis][b] += other.count[axis][b];
            }
        }
    }

    template <typename Ref>
    void add(const Ref& ref, const BinMapping& mapping, uint32_t* occupied = nullptr) {
        const __m128 lo = ref.lower4();
        const __m128 hi = ref.upper4();
        const __m128i b = mapping.bins(ref.centroid4());
        const auto bx = uint32_t(_mm_cvtsi128_si32(b));
        const auto by = uint32_t(_mm_cvtsi128_si32(_mm_shuffle_epi32(b, 0x55)));
        const auto bz = uint32_t(_mm_cvtsi128_si32(_mm_shuffle_epi32(b, 0xaa)));
        bin[0][bx].lower = _mm_min_ps(lo, bin[0][bx].lower);
        bin[0][bx].upper = _mm_max_ps(hi, bin[0][bx].upper);
        ++count[0][bx];
        bin[1][by].lower = _mm_min_ps(lo, bin[1][by].lower);
        bin[1][by].upper = _mm_max_ps(hi, bin[1][by].upper);
        ++count[1][by];
        bin[2][bz].lower = _mm_min_ps(lo, bin[2][bz].lower);
        bin[2][bz].upper = _mm_max_ps(hi, bin[2][bz].upper);
        ++count[2][bz];
        if (occupied) {
            occupied[0] |= 1u << bx;
            occupied[1] |= 1u << by;
            occupied[2] |= 1u << bz;
        }
    }

    // Bins the primitives; sets the bits of `occupied` that occupied() would
    // (for a few primitives, cheaper than reading every count afterwards).
    template <typename Ref>
    void add(const Ref* refs, uint32_t size, const BinMapping& mapping, uint32_t (&occupied)[3]) {
        if (size <= 16) {
            occupied[0] = occupied[1] = occupied[2] = 0;
            for (uint32_t i = 0; i < size; ++i) add(refs[i], mapping, occupied);
            return;
        }
        for (uint32_t i = 0; i < size; ++i) add(refs[i], mapping);
        for (int axis = 0; axis < 3; ++axis) occupied[axis] = this->occupied(axis);
    }

    // Bit b set where bin b on `axis` holds a primitive.
    uint32_t occupied(int axis) const {
        uint32_t mask = 0;
        for (uint32_t b = 0; b < kMaxBins; b += 4) {
            const __m128i counts = _mm_loadu_si128(reinterpret_cast<const __m128i*>(&count[axis][b]));
            const __m128i empty = _mm_cmpeq_epi32(counts, _mm_setzero_si128());
            mask |= uint32_t(_mm_movemask_ps(_mm_castsi128_ps(empty)) ^ 0xf) << b;
        }
        return mask;
    }

    // Resets the bins that occupied() lists, which leaves all reset.
    void clear(const uint32_t (&occupied)[3]) {
        const __m128 inf = _mm_set1_ps(kInfinity), minus_inf = _mm_set1_ps(-kInfinity);
        for (int axis = 0; axis < 3; ++axis) {
            for (uint32_t rest = occupied[axis]; rest != 0; rest &= rest - 1) {
                const auto b = uint32_t(std::countr_zero(rest));
                bin[axis][b].lower = inf;
                bin[axis][b].upper = minus_inf;
                count[axis][b] = 0;
            }
        }
    }

    // The union of the occupied bins in [begin, end) on `axis`.
    Box4 box(int axis, uint32_t occupied, uint32_t begin, uint32_t end) const {
        Box4 box;
        const uint32_t in_range = occupied & (end < 32 ? (1u << end) - 1 : ~0u) & ~((1u << begin) - 1);
        for (uint32_t rest = in_range; rest != 0; rest &= rest - 1) {
            const auto b = uint32_t(std::countr_zero(rest));
            box.extend(bin[axis][b].lower, bin[axis][b].upper);
        }
        return box;
    }

    uint32_t count_below(int axis, uint32_t bin) const {
        uint32_t total = 0;
        for (uint32_t b = 0; b < bin; ++b) total += count[axis][b];
        return total;
    }
};

// A thread's bins, reset, for the nodes it builds one after the other.
struct ScratchBins {
    BinSet bins;

    ScratchBins() { bins.reset(); }
};

struct Split {
    int axis = -1;           // -1: no axis separates the centroids
    uint32_t first_right_bin = 0;
    float cost = kInfinity;  // sum over both sides of box area times primitive cost
};

}  // namespace rt::bvh::detail
