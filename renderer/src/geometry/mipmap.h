// The mip chain of a texture (texture.h): each level is the one before it
// box-filtered to half its size, rounded down and at least 1, so a chain ends
// at 1x1 after floor(log2(max(width, height))) steps. Filtering happens on
// light, not on codes: sRGB texels are decoded, averaged and encoded again, so
// a black and white checker becomes the linear grey 0.5 (code 188), not the
// sRGB mean 0.5 of the codes (linear 0.21) that a filter on codes would give.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "geometry/texture.h"

namespace rt {

// The chain from `base` (level 0, `channels` bytes a texel) down to 1x1.
std::vector<Texture::Level> mip_chain(Texture::Level base, int channels, Texture::Encoding encoding);

// The bytes mip_chain() of a width x height x channels image takes, known
// before anything is decoded (the loaders' budget).
size_t mip_chain_bytes(int width, int height, int channels);

// The 8-bit sRGB code whose decoded value lies nearest to `linear`, so that
// encoding a decoded code gives the code back.
uint8_t encode_srgb(float linear);

}  // namespace rt
