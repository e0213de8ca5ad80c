// The hashes that key sample values by what they are for (pixel, sample index,
// dimension), so a pixel's value never depends on tiling or thread count, and
// the frame that sampling code builds around a direction. sampler.h draws the
// sample values themselves.
#pragma once

#include <cmath>
#include <cstdint>

#include "util/math.h"

namespace rt {

// A strong 32-bit integer mix (Wellons' "lowbias32"): consecutive keys give
// unrelated outputs.
inline uint32_t mix_bits(uint32_t x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

inline uint32_t hash_combine(uint32_t seed, uint32_t value) {
    return mix_bits(seed ^ (value + 0x9e3779b9u + (seed << 6) + (seed >> 2)));
}

// [0, 1) from the top 24 bits.
inline float unit_float(uint32_t bits) { return float(bits >> 8) * 0x1.0p-24f; }

// An orthonormal basis around a unit vector (Duff et al. 2017).
inline void orthonormal_basis(vec3 n, vec3& b1, vec3& b2) {
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float b = n.x * n.y * a;
    b1 = vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    b2 = vec3(b, sign + n.y * n.y * a, -n.y);
}

}  // namespace rt
