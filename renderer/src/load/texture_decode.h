// Image files decoded into the 8-bit textures of texture.h.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "geometry/material.h"

namespace rt {

// The most bytes the textures of one scene may hold together, mip levels
// included: a limit on what a hostile file can make us allocate. As much as
// 2^26 texels of linear float RGB took before textures were 8-bit; it holds
// some 140 million RGBA texels with their mips (eight 4096x4096 maps).
inline constexpr size_t kMaxSceneTextureBytes = size_t(768) << 20;

// Decodes a PNG, JPEG, BMP, TGA or WebP image into a texture of as many 8-bit
// channels as the image has (16-bit PNGs are read at 8 bits) and builds its
// mip chain; `encoding` says how its colour values are to be read (sRGB for
// base colour and emission, linear for data maps). The image's size is read
// from its header before anything is allocated: one whose texels and mips
// would take more than `byte_budget` throws SceneError naming `what`, and the
// budget shrinks by what the texture takes. Bytes that are no decodable image
// give std::nullopt and the reason in `problem`.
std::optional<Texture> decode_texture(std::span<const unsigned char> bytes, std::string_view what,
                                      Texture::Encoding encoding, size_t& byte_budget, std::string& problem);

}  // namespace rt
