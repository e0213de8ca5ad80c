#include "geometry/mipmap.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace rt {
namespace {

// The box filter that halves one axis of n texels into max(1, n / 2), as
// source texels and their weights: each target texel covers n / m source
// texels exactly. Even n gives two taps of 1/2; odd n = 2m + 1 three taps,
// (m - i) / n, m / n and (i + 1) / n (the polyphase box of NVIDIA's "Non-Power-
// of-Two Mipmapping"), so no source texel counts more than another.
struct Taps {
    int first = 0;
    int count = 1;
    float weight[3] = {1.0f, 0.0f, 0.0f};
};

Taps taps(int i, int n) {
    Taps t;
    if (n == 1) return t;
    t.first = 2 * i;
    if (n % 2 == 0) {
        t.count = 2;
        t.weight[0] = t.weight[1] = 0.5f;
        return t;
    }
    const int m = n / 2;
    t.count = 3;
    t.weight[0] = float(m - i) / float(n);
    t.weight[1] = float(m) / float(n);
    t.weight[2] = float(i + 1) / float(n);
    return t;
}

int half(int n) { return std::max(1, n / 2); }

uint8_t encode_linear(float value) { return uint8_t(std::lround(std::clamp(value, 0.0f, 1.0f) * 255.0f)); }

Texture::Level downsample(const Texture::Level& source, int channels, Texture::Encoding encoding) {
    Texture::Level out{half(source.width), half(source.height), {}};
    out.texels.resize(size_t(out.width) * size_t(out.height) * size_t(channels));
    const float* srgb = srgb_decode_table();
    // Grey + alpha and RGBA keep alpha in their last channel, always linear.
    const int colour_channels = channels == 2 || channels == 4 ? channels - 1 : channels;
    const auto decode = [&](int c, uint8_t code) {
        return c < colour_channels && encoding == Texture::Encoding::Srgb ? srgb[code] : float(code) / 255.0f;
    };
    for (int y = 0; y < out.height; ++y) {
        const Taps ty = taps(y, source.height);
        for (int x = 0; x < out.width; ++x) {
            const Taps tx = taps(x, source.width);
            float sum[4] = {0.0f, 0.0f, 0.0f, 0.0f};
            for (int j = 0; j < ty.count; ++j) {
                const uint8_t* row =
                    source.texels.data() + size_t(ty.first + j) * size_t(source.width) * size_t(channels);
                for (int i = 0; i < tx.count; ++i) {
                    const uint8_t* p = row + size_t(tx.first + i) * size_t(channels);
                    const float w = ty.weight[j] * tx.weight[i];
                    for (int c = 0; c < channels; ++c) sum[c] += w * decode(c, p[c]);
                }
            }
            uint8_t* q = out.texels.data() + (size_t(y) * size_t(out.width) + size_t(x)) * size_t(channels);
            for (int c = 0; c < channels; ++c)
                q[c] = c < colour_channels && encoding == Texture::Encoding::Srgb ? encode_srgb(sum[c])
                                                                                 : encode_linear(sum[c]);
        }
    }
    return out;
}

}  // namespace

uint8_t encode_srgb(float linear) {
    // Between codes k and k + 1 the nearer one wins: the midpoints of their
    // decoded values split the line.
    static const std::array<float, 255> midpoints = [] {
        const float* decoded = srgb_decode_table();
        std::array<float, 255> m{};
        for (size_t k = 0; k < 255; ++k) m[k] = 0.5f * (decoded[k] + decoded[k + 1]);
        return m;
    }();
    if (!(linear > 0.0f)) return 0;  // NaN too
    return uint8_t(std::lower_bound(midpoints.begin(), midpoints.end(), linear) - midpoints.begin());
}

std::vector<Texture::Level> mip_chain(Texture::Level base, int channels, Texture::Encoding encoding) {
    std::vector<Texture::Level> chain;
    chain.push_back(std::move(base));
    while (chain.back().width > 1 || chain.back().height > 1)
        chain.push_back(downsample(chain.back(), channels, encoding));
    return chain;
}

size_t mip_chain_bytes(int width, int height, int channels) {
    size_t total = 0;
    for (;;) {
        total += size_t(width) * size_t(height) * size_t(channels);
        if (width == 1 && height == 1) return total;
        width = half(width);
        height = half(height);
    }
}

}  // namespace rt
