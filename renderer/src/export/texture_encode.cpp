#include "export/texture_encode.h"

#include <cmath>
#include <stdexcept>
#include <string>

// stb_image_write, private to this file: the tests compile their own copy.
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>

#include "image/image.h"

namespace rt {

std::vector<unsigned char> encode_png(const Texture& texture) {
    const size_t texels = size_t(texture.width) * size_t(texture.height);
    if (texture.width <= 0 || texture.height <= 0 || texture.texels.size() != texels)
        throw std::invalid_argument("encode_png(): a " + std::to_string(texture.width) + "x" +
                                    std::to_string(texture.height) + " texture holds " +
                                    std::to_string(texture.texels.size()) + " texels");
    std::vector<unsigned char> srgb(3 * texels);
    for (size_t i = 0; i < texels; ++i)
        for (int c = 0; c < 3; ++c)
            srgb[3 * i + c] = (unsigned char)std::lround(linear_to_srgb(texture.texels[i][c]) * 255.0f);

    std::vector<unsigned char> png;
    const auto append = [](void* context, void* data, int size) {
        auto* out = static_cast<std::vector<unsigned char>*>(context);
        out->insert(out->end(), static_cast<unsigned char*>(data), static_cast<unsigned char*>(data) + size);
    };
    if (!stbi_write_png_to_func(append, &png, texture.width, texture.height, 3, srgb.data(), 3 * texture.width))
        throw std::runtime_error("encode_png(): stb_image_write failed on a " + std::to_string(texture.width) +
                                 "x" + std::to_string(texture.height) + " texture");
    return png;
}

}  // namespace rt
