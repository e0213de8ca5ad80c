// How a linear HDR image becomes 8-bit sRGB for a screen or a PNG: scaled by
// 2^exposure, tone mapped into [0, 1], then sRGB-encoded and rounded. Every
// 8-bit output (the CLI's PNG, the service's tiles and image.png) goes through
// encode_srgb8, so they agree byte for byte.
#pragma once

#include <cmath>
#include <cstdint>
#include <span>

#include "util/math.h"
#include "rt/render.pb.h"

namespace rt {

struct DisplayTransform {
    float exposure = 0.0f;  // stops
    ToneMap tone_map = CLIP;

    // The settings' exposure and tone_map, the schema's defaults where absent.
    // Throws std::invalid_argument naming a value out of its limits.
    static DisplayTransform from(const RenderSettings& settings);
};

// The curve alone, on exposed linear RGB: CLIP leaves it (the encoding
// clips), REINHARD scales it by 1 / (1 + L) with L its Rec. 709 luminance (hue
// kept; a saturated colour may stay above 1 and clip), ACES maps each channel
// through Narkowicz's fit into [0, 1].
vec3 tone_map(vec3 rgb, ToneMap curve);

// The sRGB transfer function (IEC 61966-2-1) of a linear value clamped to
// [0, 1]; NaN counts as 0.
float linear_to_srgb(float linear);

// The reference 8-bit code of one linear value. encode_srgb8 gives the same
// bytes from a table, several times faster.
inline uint8_t srgb8(float linear) { return uint8_t(std::lround(linear_to_srgb(linear) * 255.0f)); }

// Linear RGB (3 floats a pixel) through `display` into `out`: RGB (3 bytes a
// pixel) or RGBA with opaque alpha (4 bytes a pixel), as out's size says. With
// the default transform every byte is srgb8 of its value. Throws
// std::invalid_argument when the sizes fit neither layout.
void encode_srgb8(std::span<const float> rgb, const DisplayTransform& display, std::span<uint8_t> out);

}  // namespace rt
