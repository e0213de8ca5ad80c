// Images as materials read them, and how a material refers to one: which
// image, which texture coordinate set, and KHR_texture_transform's affine map
// of those coordinates.
#pragma once

#include <cstdint>
#include <vector>

#include "util/math.h"

namespace rt {

// An image as 8-bit texels of 1 to 4 channels (grey, grey + alpha, RGB, RGBA:
// as the file had them), with its full mip chain, sampled trilinearly.
// Colour channels are sRGB-encoded (base colour, emission: decoded at lookup
// through a 256-entry table) or linear (data maps: c / 255); alpha is always
// linear. At 8 bits a 4096x4096 RGBA map is 64 MiB and its mips a third more,
// where linear float RGB was 192 MiB without them.
struct Texture {
    enum class Wrap { Repeat, ClampToEdge, MirroredRepeat };
    enum class Encoding { Srgb, Linear };

    // One mip level: row-major, row 0 at v = 0 (the top of the image),
    // `channels` bytes a texel.
    struct Level {
        int width = 0;
        int height = 0;
        std::vector<uint8_t> texels;
    };

    int width = 0;     // of level 0
    int height = 0;
    int channels = 0;  // 1 to 4
    Encoding encoding = Encoding::Srgb;
    Wrap wrap_s = Wrap::Repeat;
    Wrap wrap_t = Wrap::Repeat;
    std::vector<Level> levels;  // levels[0] is the image, each next one half as large, down to 1x1

    Texture() = default;
    // Takes level 0 (width x height x channels bytes) and builds the mip chain
    // (mipmap.h). Throws std::invalid_argument when the sizes do not agree.
    Texture(int width, int height, int channels, Encoding encoding, std::vector<uint8_t> texels);

    // Linear RGBA at `uv`, filtered over a footprint of 2^lod texels of level
    // 0: bilinear within a level (texel centres at half-integers), linear
    // between the two levels around lod. lod 0 or less (or NaN) is bilinear on
    // level 0. Grey is (g, g, g); a missing alpha is 1. An empty texture is white.
    glm::vec4 sample(vec2 uv, float lod = 0.0f) const;

    // Texel (x, y) of `level`, decoded to linear RGBA; no wrapping.
    glm::vec4 texel(size_t level, int x, int y) const;

    // What the texels of every level take.
    size_t bytes() const;
};

// The sRGB transfer function undone: encoded value in [0, 1] to linear.
float srgb_to_linear(float encoded);

// srgb_to_linear of each 8-bit code c / 255: the table lookups decode through.
const float* srgb_decode_table();

// KHR_texture_transform: uv' = T(offset) R(rotation) S(scale) uv, rotation in
// radians counter-clockwise in uv space (which, with v down the image, turns
// the image clockwise), as the extension defines it.
struct TextureTransform {
    vec2 offset{0.0f};
    float rotation = 0.0f;
    vec2 scale{1.0f};

    bool identity() const { return offset == vec2(0.0f) && rotation == 0.0f && scale == vec2(1.0f); }
    vec2 apply(vec2 uv) const {
        const float c = std::cos(rotation), s = std::sin(rotation);
        const vec2 scaled = uv * scale;
        return vec2(c * scaled.x + s * scaled.y, -s * scaled.x + c * scaled.y) + offset;
    }
};

struct TextureRef {
    int index = -1;         // into Scene::textures; -1 for none
    uint32_t texcoord = 0;  // TEXCOORD_n: 0 or 1
    TextureTransform transform;

    explicit operator bool() const { return index >= 0; }
};

}  // namespace rt
