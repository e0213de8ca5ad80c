// Textures written back as image files: the inverse of texture_decode.h, for
// exporting a loaded scene (glb_export.h).
#pragma once

#include <vector>

#include "geometry/material.h"

namespace rt {

// The texture as an 8-bit sRGB PNG, row 0 on top: each linear texel goes
// through the sRGB transfer function and is rounded, so a texture decoded from
// an 8-bit sRGB image encodes back to the very same values.
std::vector<unsigned char> encode_png(const Texture& texture);

}  // namespace rt
