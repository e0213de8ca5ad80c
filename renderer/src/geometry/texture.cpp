#include "geometry/texture.h"

#include <algorithm>
#include <cmath>

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

vec3 Texture::sample(vec2 uv) const {
    if (width <= 0 || height <= 0 || texels.size() != size_t(width) * size_t(height)) return vec3(1.0f);
    // A NaN coordinate would make every index below meaningless; texel 0 it is.
    const float u = std::isfinite(uv.x) ? uv.x : 0.0f;
    const float v = std::isfinite(uv.y) ? uv.y : 0.0f;

    // Texel centres sit at half-integers: texel i covers [i, i + 1) in texel units.
    const float x = reduce(u, wrap_s) * float(width) - 0.5f;
    const float y = reduce(v, wrap_t) * float(height) - 0.5f;
    const float fx0 = std::floor(x), fy0 = std::floor(y);
    const float tx = x - fx0, ty = y - fy0;
    const int x0 = int(fx0), y0 = int(fy0);

    const int xa = wrap_index(x0, width, wrap_s), xb = wrap_index(x0 + 1, width, wrap_s);
    const int ya = wrap_index(y0, height, wrap_t), yb = wrap_index(y0 + 1, height, wrap_t);
    const auto at = [&](int xi, int yi) { return texels[size_t(yi) * size_t(width) + size_t(xi)]; };
    const vec3 top = glm::mix(at(xa, ya), at(xb, ya), tx);
    const vec3 bottom = glm::mix(at(xa, yb), at(xb, yb), tx);
    return glm::mix(top, bottom, ty);
}

}  // namespace rt
