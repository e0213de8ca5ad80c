// A linear-RGB float image and how it is written: PNG as sRGB 8-bit, EXR as
// linear float, both through OpenImageIO.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

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

// Format by extension (.png or .exr). Throws std::runtime_error naming the file.
void write_image(const std::filesystem::path& file, const Image& image);

}  // namespace rt
