#include "load/texture_decode.h"

#include <array>
#include <climits>
#include <cmath>
#include <memory>

#include <stb_image.h>

#include "load/loader.h"

namespace rt {

float srgb_to_linear(float encoded) {
    return encoded <= 0.04045f ? encoded / 12.92f : std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

std::optional<Texture> decode_texture(std::span<const unsigned char> bytes, std::string_view what,
                                      size_t& texel_budget, std::string& problem) {
    if (bytes.empty() || bytes.size() > size_t(INT_MAX)) {
        problem = bytes.empty() ? "is empty" : "is too large to decode";
        return std::nullopt;
    }
    const int length = int(bytes.size());
    int width = 0, height = 0, channels = 0;
    if (!stbi_info_from_memory(bytes.data(), length, &width, &height, &channels) || width <= 0 ||
        height <= 0) {
        problem = std::string("is not a PNG, JPEG, BMP or TGA image (") + stbi_failure_reason() + ")";
        return std::nullopt;
    }
    const size_t texels = size_t(width) * size_t(height);
    if (texels > texel_budget)
        throw SceneError(std::string(what) + " is " + std::to_string(width) + "x" +
                         std::to_string(height) + " texels: the scene's textures would exceed the "
                         "limit of " + std::to_string(kMaxSceneTexels) + " texels");

    int decoded_width = 0, decoded_height = 0;
    const std::unique_ptr<stbi_uc, void (*)(void*)> pixels(
        stbi_load_from_memory(bytes.data(), length, &decoded_width, &decoded_height, &channels, 3),
        stbi_image_free);
    // The header may promise another size than the data holds; trust neither alone.
    if (!pixels || decoded_width != width || decoded_height != height) {
        problem = std::string("cannot be decoded (") + (pixels ? "size changed" : stbi_failure_reason()) + ")";
        return std::nullopt;
    }

    static const std::array<float, 256> linear = [] {
        std::array<float, 256> table{};
        for (int i = 0; i < 256; ++i) table[size_t(i)] = srgb_to_linear(float(i) / 255.0f);
        return table;
    }();
    Texture texture;
    texture.width = width;
    texture.height = height;
    texture.texels.resize(texels);
    for (size_t i = 0; i < texels; ++i) {
        const stbi_uc* p = pixels.get() + 3 * i;
        texture.texels[i] = vec3(linear[p[0]], linear[p[1]], linear[p[2]]);
    }
    texel_budget -= texels;
    return texture;
}

}  // namespace rt
