// Deterministic sample values keyed by what they are for (pixel, sample index,
// dimension), so a pixel's value never depends on tiling or thread count.
#pragma once

#include <cmath>
#include <cstdint>

#include "math.h"

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

// Sample `index` of `count` points jittered in a sqrt(count) x sqrt(count) grid
// (the remainder, when count is not square, is drawn uniformly).
inline vec2 stratified_2d(uint32_t index, uint32_t count, uint32_t key) {
    const uint32_t side = uint32_t(std::sqrt(float(count)));
    const uint32_t h = mix_bits(key ^ mix_bits(index));
    const vec2 jitter(unit_float(h), unit_float(mix_bits(h)));
    if (index < side * side) {
        const vec2 cell(float(index % side), float(index / side));
        return (cell + jitter) / float(side);
    }
    return jitter;
}

// Uniform in solid angle over the cone around +z with half-angle acos(cos_max)
// (pbrt-v4, SampleUniformCone).
inline vec3 sample_uniform_cone(vec2 u, float cos_max) {
    const float cos_theta = (1.0f - u.x) + u.x * cos_max;
    const float sin_theta = std::sqrt(glm::max(0.0f, 1.0f - cos_theta * cos_theta));
    const float phi = 2.0f * kPi * u.y;
    return {std::cos(phi) * sin_theta, std::sin(phi) * sin_theta, cos_theta};
}

// An orthonormal basis around a unit vector (Duff et al. 2017).
inline void orthonormal_basis(vec3 n, vec3& b1, vec3& b2) {
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float b = n.x * n.y * a;
    b1 = vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    b2 = vec3(b, sign + n.y * n.y * a, -n.y);
}

}  // namespace rt
