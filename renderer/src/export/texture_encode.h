// Textures written back as image files: the inverse of texture_decode.h, for
// exporting a loaded scene (glb_export.h).
#pragma once

#include <vector>

#include "geometry/material.h"

namespace rt {

// Level 0 of the texture as an 8-bit PNG of as many channels (grey, grey +
// alpha, RGB, RGBA), row 0 on top: the very codes the texture was decoded
// from, so decoding the PNG gives the same texture back.
std::vector<unsigned char> encode_png(const Texture& texture);

}  // namespace rt
