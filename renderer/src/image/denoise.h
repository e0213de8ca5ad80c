// Denoising (rt.RenderSettings denoise): the noise of sampled effects taken
// out of a finished linear image by Intel Open Image Denoise's "RT" filter,
// which a network trained on path-traced images drives, with the albedo and
// normal layers (aov.h) as guides so that edges and textures stay sharp.
#pragma once

#include <cstdint>
#include <string>

#include "image/aov.h"
#include "image/image.h"
#include "rt/render.pb.h"

namespace rt {

// The layers a denoiser needs beyond colour: albedo and normal for OIDN,
// none without denoising.
std::vector<AuxOutput> denoise_guides(const RenderSettings& settings);

// Denoises `image` in place with `guides`' albedo and normal layers (which
// must be there, of the image's size) when `settings` ask for it; leaves it
// untouched otherwise. Pixels that are not finite keep their values and are
// given to the filter as black, so one NaN cannot spread over its
// neighbourhood. `threads` caps OIDN's (0: all cores). The same input gives
// the same output bit for bit. Throws std::runtime_error when OIDN cannot be
// loaded or fails, std::invalid_argument for missing guides.
void apply_denoise(Image& image, const AuxImage& guides, const RenderSettings& settings, unsigned threads = 0);

// The same on raw arrays of width * height * 3 floats: `color` in, `out`
// written (they may be the same array).
void denoise_oidn(uint32_t width, uint32_t height, const float* color, const float* albedo, const float* normal,
                  float* out, unsigned threads = 0);

}  // namespace rt
