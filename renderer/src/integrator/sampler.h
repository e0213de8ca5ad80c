// The sample values of one pixel sample, keyed by pixel, sample index and
// dimension, never by tile or thread.
//
// Each dimension (the film position, the shutter time, each light at each
// bounce) draws 2D points from its own copy of the Sobol' (0,2)-sequence,
// shuffled and Owen-scrambled by hashing (Burley 2020, "Practical Hash-based
// Owen Scrambling"). Scrambling keeps the sequence's stratification, so the
// first 2^m points of a dimension fall one in each elementary interval of area
// 2^-m whatever the pixel; the shuffle, seeded differently per dimension, keeps
// dimensions uncorrelated.
#pragma once

#include <cstdint>

#include "util/math.h"
#include "integrator/sampling.h"

namespace rt {

inline uint32_t reverse_bits(uint32_t x) {
    x = (x << 16) | (x >> 16);
    x = ((x & 0x00ff00ffu) << 8) | ((x & 0xff00ff00u) >> 8);
    x = ((x & 0x0f0f0f0fu) << 4) | ((x & 0xf0f0f0f0u) >> 4);
    x = ((x & 0x33333333u) << 2) | ((x & 0xccccccccu) >> 2);
    return ((x & 0x55555555u) << 1) | ((x & 0xaaaaaaaau) >> 1);
}

// Laine and Karras' permutation, with Burley's constants: each bit is flipped
// or not by a hash of the bits below it (multiplications by even constants
// carry only upwards).
inline uint32_t laine_karras_permutation(uint32_t x, uint32_t seed) {
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

// Owen scrambling of a 32-bit fraction (its top bit is the first binary digit):
// each digit is flipped or not by a hash of the digits before it, which in
// reversed bit order is the Laine-Karras permutation.
inline uint32_t nested_uniform_scramble(uint32_t x, uint32_t seed) {
    return reverse_bits(laine_karras_permutation(reverse_bits(x), seed));
}

// Sobol's second dimension as a 32-bit fraction: the generator matrix is
// Pascal's triangle mod 2. (The first is van der Corput's, reverse_bits.) The
// matrix-vector product over GF(2) is the XOR of its columns for the index's
// set bits, taken a byte at a time from tables built at compile time.
struct SobolDimension1Tables {
    uint32_t byte[4][256];

    constexpr SobolDimension1Tables() : byte{} {
        uint32_t column[32] = {};
        for (uint32_t k = 0, v = 1u << 31; k < 32; ++k, v ^= v >> 1) column[k] = v;
        for (uint32_t b = 0; b < 4; ++b)
            for (uint32_t value = 0; value < 256; ++value)
                for (uint32_t bit = 0; bit < 8; ++bit)
                    if (value & (1u << bit)) byte[b][value] ^= column[8 * b + bit];
    }
};
inline constexpr SobolDimension1Tables kSobolDimension1;

inline uint32_t sobol_dimension_1(uint32_t index) {
    const auto& t = kSobolDimension1.byte;
    return t[0][index & 0xffu] ^ t[1][(index >> 8) & 0xffu] ^ t[2][(index >> 16) & 0xffu] ^ t[3][index >> 24];
}

// Point `index` of the scrambled, shuffled (0,2)-sequence that `seed` selects.
// Scrambling the index like a fraction in reversed bit order permutes it within
// every aligned block of 2^m indices (as far as its low m bits go), which is all
// the block's stratification depends on.
inline vec2 scrambled_sobol_2d(uint32_t index, uint32_t seed) {
    index = nested_uniform_scramble(index, mix_bits(seed ^ 0x2c1b3c6du));
    // Van der Corput's point is reverse_bits(index): scrambling it reverses it back first.
    const uint32_t x = reverse_bits(laine_karras_permutation(index, mix_bits(seed ^ 0x297a2d39u)));
    const uint32_t y = nested_uniform_scramble(sobol_dimension_1(index), mix_bits(seed ^ 0x46e1d9a5u));
    return {unit_float(x), unit_float(y)};
}

class PixelSampler {
  public:
    // `pixel_key` identifies the pixel (any hash of its coordinates); `sample`
    // is the pixel sample's index.
    PixelSampler(uint32_t pixel_key, uint32_t sample) : key_(pixel_key), sample_(sample) {}

    uint32_t sample() const { return sample_; }

    // Where the pixel sample lies within its pixel's filter, as a point of [0,1)^2.
    vec2 film() const { return scrambled_sobol_2d(sample_, hash_combine(key_, kFilmDimension)); }

    // When in the shutter interval, [0, 1), the pixel sample is taken: one
    // coordinate of its own sequence, which alone is stratified as well.
    float time() const { return scrambled_sobol_2d(sample_, hash_combine(key_, kTimeDimension)).x; }

    // Point `i` of the `count` points this pixel sample takes in `dimension` (a
    // light's index). Pixel sample s takes the points s * count to s * count +
    // count - 1 of the dimension's sequence: together the pixel's samples
    // stratify the dimension, rather than each repeating the same pattern.
    vec2 get_2d(uint32_t dimension, uint32_t i, uint32_t count) const {
        return scrambled_sobol_2d(sample_ * count + i, hash_combine(key_, dimension));
    }

    // The sampler for what a reflection at `depth` computes: the same pixel
    // sample, fresh dimensions.
    PixelSampler bounce(uint32_t depth) const { return {hash_combine(key_, depth), sample_}; }

  private:
    // No light index reaches these.
    static constexpr uint32_t kFilmDimension = 0xffffffffu;
    static constexpr uint32_t kTimeDimension = 0xfffffffeu;

    uint32_t key_;
    uint32_t sample_;
};

}  // namespace rt
