#include "load/texture_decode.h"

#include <climits>
#include <memory>

#include <stb_image.h>
#include <webp/decode.h>

#include "geometry/mipmap.h"
#include "load/loader.h"

namespace rt {
namespace {

// What an image's header says, read before any texel is decoded.
struct ImageHeader {
    int width = 0;
    int height = 0;
    int channels = 0;
    bool webp = false;
};

bool read_header(std::span<const unsigned char> bytes, ImageHeader& header, std::string& problem) {
    WebPBitstreamFeatures features;
    if (WebPGetFeatures(bytes.data(), bytes.size(), &features) == VP8_STATUS_OK) {
        header = {features.width, features.height, features.has_alpha ? 4 : 3, true};
        return true;
    }
    if (!stbi_info_from_memory(bytes.data(), int(bytes.size()), &header.width, &header.height, &header.channels)) {
        problem = std::string("is not a PNG, JPEG, BMP, TGA or WebP image (") + stbi_failure_reason() + ")";
        return false;
    }
    return true;
}

// The texels, `header.channels` bytes each, or empty when the data does not
// hold the image its header promised. The decoders allocate their output with
// malloc, untouched until they write it, so a header that lies about its size
// costs no memory; the copy into the texture's own vector is brief.
std::vector<uint8_t> decode_texels(std::span<const unsigned char> bytes, const ImageHeader& header,
                                   std::string& problem) {
    const size_t size = size_t(header.width) * size_t(header.height) * size_t(header.channels);
    int width = 0, height = 0, channels = 0;
    std::unique_ptr<uint8_t, void (*)(void*)> pixels(nullptr, stbi_image_free);
    if (header.webp) {
        // libwebp gives unassociated alpha, as glTF means it.
        pixels = std::unique_ptr<uint8_t, void (*)(void*)>(
            header.channels == 4 ? WebPDecodeRGBA(bytes.data(), bytes.size(), &width, &height)
                                 : WebPDecodeRGB(bytes.data(), bytes.size(), &width, &height),
            WebPFree);
        if (!pixels) problem = "cannot be decoded (a broken WebP stream)";
    } else {
        pixels.reset(
            stbi_load_from_memory(bytes.data(), int(bytes.size()), &width, &height, &channels, header.channels));
        if (!pixels) problem = std::string("cannot be decoded (") + stbi_failure_reason() + ")";
    }
    if (!pixels) return {};
    // The header may promise another size than the data holds; trust neither alone.
    if (width != header.width || height != header.height) {
        problem = "cannot be decoded (size changed)";
        return {};
    }
    return std::vector<uint8_t>(pixels.get(), pixels.get() + size);
}

}  // namespace

std::optional<Texture> decode_texture(std::span<const unsigned char> bytes, std::string_view what,
                                      Texture::Encoding encoding, size_t& byte_budget, std::string& problem) {
    if (bytes.empty() || bytes.size() > size_t(INT_MAX)) {
        problem = bytes.empty() ? "is empty" : "is too large to decode";
        return std::nullopt;
    }
    ImageHeader header;
    if (!read_header(bytes, header, problem)) return std::nullopt;
    if (header.width <= 0 || header.height <= 0 || header.channels < 1 || header.channels > 4) {
        problem = "has no texels we can read";
        return std::nullopt;
    }
    const size_t needed = mip_chain_bytes(header.width, header.height, header.channels);
    if (needed > byte_budget)
        throw SceneError(std::string(what) + " is " + std::to_string(header.width) + "x" +
                         std::to_string(header.height) + " texels: the scene's textures would exceed the limit of " +
                         std::to_string(kMaxSceneTextureBytes >> 20) + " MiB (8-bit texels and their mip levels)");
    std::vector<uint8_t> texels = decode_texels(bytes, header, problem);
    if (texels.empty()) return std::nullopt;
    byte_budget -= needed;
    return Texture(header.width, header.height, header.channels, encoding, std::move(texels));
}

}  // namespace rt
