#include "export/texture_encode.h"

#include <stdexcept>
#include <string>

// stb_image_write, private to this file: the tests compile their own copy.
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>

namespace rt {

std::vector<unsigned char> encode_png(const Texture& texture) {
    if (texture.levels.empty() || texture.channels < 1 || texture.channels > 4 ||
        texture.levels[0].texels.size() != size_t(texture.width) * size_t(texture.height) * size_t(texture.channels))
        throw std::invalid_argument("encode_png(): a " + std::to_string(texture.width) + "x" +
                                    std::to_string(texture.height) + " texture of " +
                                    std::to_string(texture.channels) + " channels without its texels");
    // The stored codes are the file's: sRGB or linear, as the material slot reads them.
    const std::vector<uint8_t>& texels = texture.levels[0].texels;
    std::vector<unsigned char> png;
    const auto append = [](void* context, void* data, int size) {
        auto* out = static_cast<std::vector<unsigned char>*>(context);
        out->insert(out->end(), static_cast<unsigned char*>(data), static_cast<unsigned char*>(data) + size);
    };
    if (!stbi_write_png_to_func(append, &png, texture.width, texture.height, texture.channels, texels.data(),
                                texture.channels * texture.width))
        throw std::runtime_error("encode_png(): stb_image_write failed on a " + std::to_string(texture.width) +
                                 "x" + std::to_string(texture.height) + " texture");
    return png;
}

}  // namespace rt
