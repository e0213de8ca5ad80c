// Bloom: the light a lens scatters around very bright pixels, applied to the
// linear image once every tile is in (rt.RenderSettings bloom_*).
#pragma once

#include "image/image.h"
#include "rt/render.pb.h"

namespace rt {

// Moves bloom_strength s of each pixel's light above bloom_threshold into a
// Gaussian glow of standard deviation bloom_radius / 3 around it:
//
//   out = p - s bright(p) + s G(bright),  bright(p) = p max(0, L(p) - threshold) / L(p)
//
// with L the Rec. 709 luminance, so bright keeps the pixel's hue. G is
// separable and keeps every pixel's light inside the image: near a border a
// pixel's weights are renormalised over the pixels inside, so the image's sum
// is unchanged (to float rounding) whatever the strength. A pixel that is not
// finite is not spread. Leaves the image untouched when the strength is 0 or
// no pixel exceeds the threshold. Runs on OpenImageIO's thread pool. Throws
// std::invalid_argument naming a setting outside its limits.
void apply_bloom(Image& image, const RenderSettings& settings);

}  // namespace rt
