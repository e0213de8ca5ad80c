// A linear-RGB float image and how it is written: PNG as sRGB 8-bit, EXR as
// linear float with any auxiliary outputs as further channels, both through
// OpenImageIO.
#pragma once

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "aov.h"
#include "math.h"

namespace rt {

struct Image {
    uint32_t width = 0;
    uint32_t height = 0;
    std::vector<float> rgb;  // 3 floats per pixel, rows top to bottom

    Image() = default;
    Image(uint32_t w, uint32_t h) : width(w), height(h), rgb(size_t(w) * h * 3, 0.0f) {}
    vec3 pixel(uint32_t x, uint32_t y) const {
        const float* p = &rgb[(size_t(y) * width + x) * 3];
        return {p[0], p[1], p[2]};
    }
};

// The sRGB transfer function (IEC 61966-2-1) of a linear value clamped to [0, 1].
float linear_to_srgb(float linear);

// A linear value as the 8-bit sRGB code a PNG stores: every 8-bit output (the
// CLI's PNG, the service's tiles and image.png) rounds through this one function.
inline uint8_t srgb8(float linear) { return uint8_t(std::lround(linear_to_srgb(linear) * 255.0f)); }

// Format by extension (.png or .exr). An EXR holds R, G, B and then the
// channels of each layer `aux` holds (aux_channel_names: "depth.Z", ...), BVH
// costs as floats. Throws std::invalid_argument for auxiliary layers in a PNG,
// which holds colour only, and std::runtime_error naming the file when writing fails.
void write_image(const std::filesystem::path& file, const Image& image, const AuxImage* aux = nullptr);

}  // namespace rt
