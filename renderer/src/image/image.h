// A linear-RGB float image and how it is written: PNG as 8-bit sRGB after the
// display transform, EXR as linear float with any auxiliary outputs as further
// channels, both through OpenImageIO.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "image/aov.h"
#include "image/display.h"
#include "util/math.h"

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

// Format by extension (.png or .exr). A PNG holds the colour through
// `display` (exposure, tone map, sRGB 8-bit). An EXR holds the linear R, G, B
// and then the channels of each layer `aux` holds (aux_channel_names:
// "depth.Z", ...), BVH costs as floats, and last the image before denoising,
// when given ("noisy.R", "noisy.G", "noisy.B"). Throws std::invalid_argument
// for auxiliary layers or a noisy image in a PNG, which holds colour only, and
// std::runtime_error naming the file when writing fails.
void write_image(const std::filesystem::path& file, const Image& image, const AuxImage* aux = nullptr,
                 const DisplayTransform& display = {}, const Image* noisy = nullptr);

}  // namespace rt
