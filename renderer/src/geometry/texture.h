// Images as materials read them, and how a material refers to one: which
// image, which texture coordinate set, and KHR_texture_transform's affine map
// of those coordinates.
#pragma once

#include <cstdint>
#include <vector>

#include "util/math.h"

namespace rt {

// An image in linear RGB, sampled bilinearly.
struct Texture {
    enum class Wrap { Repeat, ClampToEdge, MirroredRepeat };

    int width = 0;
    int height = 0;
    std::vector<vec3> texels;  // row-major, row 0 at v = 0 (top of the image)
    Wrap wrap_s = Wrap::Repeat;
    Wrap wrap_t = Wrap::Repeat;

    vec3 sample(vec2 uv) const;
};

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
