#include "geometry/texture.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "geometry/mipmap.h"

namespace rt {
namespace {

// Brings a texture coordinate into one or two periods of its wrap mode before it
// is scaled to texels, so that any finite coordinate, however large, gives texel
// indices well inside the range of int.
float reduce(float u, Texture::Wrap wrap) {
    switch (wrap) {
        case Texture::Wrap::Repeat: return u - std::floor(u);
        case Texture::Wrap::MirroredRepeat: return u - 2.0f * std::floor(0.5f * u);
        case Texture::Wrap::ClampToEdge: break;
    }
    return std::clamp(u, -1.0f, 2.0f);
}

int wrap_index(int i, int n, Texture::Wrap wrap) {
    switch (wrap) {
        case Texture::Wrap::Repeat: {
            const int m = i % n;
            return m < 0 ? m + n : m;
        }
        case Texture::Wrap::MirroredRepeat: {
            // Texels 0..n-1 then n-1..0, so the edge texel repeats at each mirror.
            const int period = 2 * n;
            int m = i % period;
            if (m < 0) m += period;
            return m < n ? m : period - 1 - m;
        }
        case Texture::Wrap::ClampToEdge: break;
    }
    return std::clamp(i, 0, n - 1);
}

}  // namespace

float srgb_to_linear(float encoded) {
    return encoded <= 0.04045f ? encoded / 12.92f : std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

const float* srgb_decode_table() {
    static const std::array<float, 256> table = [] {
        std::array<float, 256> t{};
        for (int i = 0; i < 256; ++i) t[size_t(i)] = srgb_to_linear(float(i) / 255.0f);
        return t;
    }();
    return table.data();
}

Texture::Texture(int width_, int height_, int channels_, Encoding encoding_, std::vector<uint8_t> texels)
    : width(width_), height(height_), channels(channels_), encoding(encoding_) {
    if (width <= 0 || height <= 0 || channels < 1 || channels > 4 ||
        texels.size() != size_t(width) * size_t(height) * size_t(channels))
        throw std::invalid_argument("Texture(): a " + std::to_string(width) + "x" + std::to_string(height) + "x" +
                                    std::to_string(channels) + " texture given " + std::to_string(texels.size()) +
                                    " bytes");
    levels = mip_chain(Level{width, height, std::move(texels)}, channels, encoding);
}

glm::vec4 Texture::texel(size_t level, int x, int y) const {
    const Level& l = levels[level];
    const uint8_t* p = l.texels.data() + (size_t(y) * size_t(l.width) + size_t(x)) * size_t(channels);
    // The table holds either decoding: sRGB, or c / 255 for linear data.
    static const std::array<float, 256> linear = [] {
        std::array<float, 256> t{};
        for (int i = 0; i < 256; ++i) t[size_t(i)] = float(i) / 255.0f;
        return t;
    }();
    const float* colour = encoding == Encoding::Srgb ? srgb_decode_table() : linear.data();
    switch (channels) {
        case 1: return glm::vec4(vec3(colour[p[0]]), 1.0f);
        case 2: return glm::vec4(vec3(colour[p[0]]), linear[p[1]]);
        case 3: return glm::vec4(colour[p[0]], colour[p[1]], colour[p[2]], 1.0f);
        default: return glm::vec4(colour[p[0]], colour[p[1]], colour[p[2]], linear[p[3]]);
    }
}

namespace {

// Bilinear on one level, (u, v) already finite.
glm::vec4 bilinear(const Texture& t, size_t level, float u, float v) {
    const Texture::Level& l = t.levels[level];
    // Texel centres sit at half-integers: texel i covers [i, i + 1) in texel units.
    const float x = reduce(u, t.wrap_s) * float(l.width) - 0.5f;
    const float y = reduce(v, t.wrap_t) * float(l.height) - 0.5f;
    const float fx0 = std::floor(x), fy0 = std::floor(y);
    const float tx = x - fx0, ty = y - fy0;
    const int x0 = int(fx0), y0 = int(fy0);

    const int xa = wrap_index(x0, l.width, t.wrap_s), xb = wrap_index(x0 + 1, l.width, t.wrap_s);
    const int ya = wrap_index(y0, l.height, t.wrap_t), yb = wrap_index(y0 + 1, l.height, t.wrap_t);
    const glm::vec4 top = glm::mix(t.texel(level, xa, ya), t.texel(level, xb, ya), tx);
    const glm::vec4 bottom = glm::mix(t.texel(level, xa, yb), t.texel(level, xb, yb), tx);
    return glm::mix(top, bottom, ty);
}

}  // namespace

glm::vec4 Texture::sample(vec2 uv, float lod) const {
    if (levels.empty()) return glm::vec4(1.0f);
    // A NaN coordinate would make every index below meaningless; texel 0 it is.
    const float u = std::isfinite(uv.x) ? uv.x : 0.0f;
    const float v = std::isfinite(uv.y) ? uv.y : 0.0f;
    // Written so that a NaN lod takes level 0 too.
    if (!(lod > 0.0f)) return bilinear(*this, 0, u, v);
    const float last = float(levels.size() - 1);
    if (lod >= last) return bilinear(*this, levels.size() - 1, u, v);
    const float below = std::floor(lod);
    const size_t level = size_t(below);
    return glm::mix(bilinear(*this, level, u, v), bilinear(*this, level + 1, u, v), lod - below);
}

size_t Texture::bytes() const {
    size_t total = 0;
    for (const Level& l : levels) total += l.texels.size();
    return total;
}

}  // namespace rt
