// Image files decoded into the linear-RGB textures of material.h.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "geometry/material.h"

namespace rt {

// The most texels the textures of one scene may hold together: at 12 bytes a
// texel that is 768 MiB, and a limit on what a hostile file can make us allocate.
inline constexpr size_t kMaxSceneTexels = size_t(1) << 26;

// Decodes a PNG, JPEG, BMP or TGA image whose 8-bit colour values are sRGB
// encoded (glTF base colour, MTL map_Kd) into linear texels; alpha is dropped.
// The image's size is read from its header before anything is allocated: one
// with more texels than `texel_budget` throws SceneError naming `what`, and the
// budget shrinks by what the texture uses. Bytes that are no decodable image
// give std::nullopt and the reason in `problem`.
std::optional<Texture> decode_texture(std::span<const unsigned char> bytes, std::string_view what,
                                      size_t& texel_budget, std::string& problem);

// The sRGB transfer function undone: encoded value in [0, 1] to linear.
float srgb_to_linear(float encoded);

}  // namespace rt
