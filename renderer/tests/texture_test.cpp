// 8-bit textures and their mip chains: filtering in linear space, odd sizes,
// trilinear sampling that is the old bilinear at level 0, wrap modes at every
// level, byte-exact round trips through PNG and WebP, and what they cost.
#include "geometry/texture.h"

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <webp/encode.h>

#include "export/texture_encode.h"
#include "geometry/mipmap.h"
#include "load/texture_decode.h"

namespace rt {
namespace {

using Encoding = Texture::Encoding;
using Wrap = Texture::Wrap;

// An image of random codes.
Texture random_texture(int width, int height, int channels, Encoding encoding, uint32_t seed) {
    std::mt19937 random(seed);
    std::vector<uint8_t> texels(size_t(width) * size_t(height) * size_t(channels));
    for (uint8_t& t : texels) t = uint8_t(random() & 0xff);
    return Texture(width, height, channels, encoding, std::move(texels));
}

// The bilinear lookup textures had before they were 8-bit and mipmapped, on
// level 0's decoded texels, written out again here as the reference.
glm::vec4 old_bilinear(const Texture& t, vec2 uv) {
    const auto reduce = [](float u, Wrap wrap) {
        if (wrap == Wrap::Repeat) return u - std::floor(u);
        if (wrap == Wrap::MirroredRepeat) return u - 2.0f * std::floor(0.5f * u);
        return std::clamp(u, -1.0f, 2.0f);
    };
    const auto index = [](int i, int n, Wrap wrap) {
        if (wrap == Wrap::Repeat) return ((i % n) + n) % n;
        if (wrap == Wrap::MirroredRepeat) {
            const int m = ((i % (2 * n)) + 2 * n) % (2 * n);
            return m < n ? m : 2 * n - 1 - m;
        }
        return std::clamp(i, 0, n - 1);
    };
    const float x = reduce(uv.x, t.wrap_s) * float(t.width) - 0.5f, y = reduce(uv.y, t.wrap_t) * float(t.height) - 0.5f;
    const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
    const float tx = x - std::floor(x), ty = y - std::floor(y);
    const auto at = [&](int i, int j) {
        return t.texel(0, index(i, t.width, t.wrap_s), index(j, t.height, t.wrap_t));
    };
    return glm::mix(glm::mix(at(x0, y0), at(x0 + 1, y0), tx), glm::mix(at(x0, y0 + 1), at(x0 + 1, y0 + 1), tx), ty);
}

void expect_near(glm::vec4 a, glm::vec4 b, float tolerance, const std::string& where) {
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(a[c], b[c], tolerance) << where << " channel " << c;
}

TEST(Texture, CheckerMipIsTheLinearMeanNotTheSrgbMean) {
    // Black and white sRGB texels: light averages to 0.5, the codes to 127.5
    // (linear 0.21), which is what filtering the stored bytes would give.
    const Texture t(2, 2, 3, Encoding::Srgb, {0, 0, 0, 255, 255, 255, 255, 255, 255, 0, 0, 0});
    ASSERT_EQ(t.levels.size(), 2u);
    EXPECT_EQ(t.levels[1].width, 1);
    EXPECT_EQ(t.levels[1].height, 1);
    const glm::vec4 mean = t.texel(1, 0, 0);
    EXPECT_EQ(t.levels[1].texels[0], 188) << "0.5 is nearest code 188 (0.5029)";
    EXPECT_NEAR(mean.r, 0.5f, 0.004f);
    EXPECT_GT(std::abs(mean.r - srgb_to_linear(127.5f / 255.0f)), 0.25f);
    expect_near(t.sample({0.3f, 0.7f}, 1.0f), mean, 1e-6f, "lod 1 is the 1x1 level");
    expect_near(t.sample({0.3f, 0.7f}, 7.0f), mean, 1e-6f, "past the last level: the last level");

    // Linear data averages its codes: 127.5 rounds to 128.
    const Texture data(2, 2, 1, Encoding::Linear, {0, 255, 255, 0});
    EXPECT_EQ(data.levels[1].texels[0], 128);
}

TEST(Texture, AlphaIsAveragedLinearlyInSrgbTextures) {
    const Texture t(2, 1, 4, Encoding::Srgb, {255, 255, 255, 0, 255, 255, 255, 255});
    ASSERT_EQ(t.levels.size(), 2u);
    EXPECT_EQ(t.levels[1].texels[3], 128);  // alpha 0.5, not sRGB-encoded
    EXPECT_EQ(t.levels[1].texels[0], 255);
}

TEST(Texture, OddSizesKeepTheMeanAtEveryLevel) {
    for (const auto& [w, h] : {std::pair{5, 3}, std::pair{7, 1}, std::pair{1, 9}, std::pair{13, 6}}) {
        const Texture t = random_texture(w, h, 1, Encoding::Linear, uint32_t(w * 31 + h));
        const auto mean = [&](size_t l) {
            double sum = 0.0;
            for (uint8_t c : t.levels[l].texels) sum += c;
            return sum / double(t.levels[l].texels.size());
        };
        int lw = w, lh = h;
        for (size_t l = 0; l < t.levels.size(); ++l) {
            EXPECT_EQ(t.levels[l].width, lw);
            EXPECT_EQ(t.levels[l].height, lh);
            lw = std::max(1, lw / 2);
            lh = std::max(1, lh / 2);
            // The exact box filter gives every texel the same weight: only rounding moves the mean.
            EXPECT_NEAR(mean(l), mean(0), 0.5 * double(l) + 1e-9) << w << "x" << h << " level " << l;
        }
        EXPECT_EQ(t.levels.back().width * t.levels.back().height, 1);
    }
}

TEST(Texture, LodZeroIsTheOldBilinear) {
    std::mt19937 random(3);
    std::uniform_real_distribution<float> coordinate(-3.0f, 3.0f);
    for (const Wrap wrap : {Wrap::Repeat, Wrap::ClampToEdge, Wrap::MirroredRepeat}) {
        for (int channels = 1; channels <= 4; ++channels) {
            Texture t = random_texture(5, 3, channels, channels % 2 ? Encoding::Srgb : Encoding::Linear, 11);
            t.wrap_s = wrap;
            t.wrap_t = wrap == Wrap::Repeat ? Wrap::MirroredRepeat : wrap;
            for (int i = 0; i < 200; ++i) {
                const vec2 uv(coordinate(random), coordinate(random));
                const glm::vec4 expected = old_bilinear(t, uv);
                EXPECT_EQ(t.sample(uv, 0.0f), expected);
                EXPECT_EQ(t.sample(uv), expected);
                EXPECT_EQ(t.sample(uv, -4.0f), expected) << "a footprint under a texel is level 0";
                EXPECT_EQ(t.sample(uv, std::numeric_limits<float>::quiet_NaN()), expected);
            }
        }
    }
}

TEST(Texture, TrilinearBlendsTheTwoLevelsAroundTheLod) {
    const Texture t = random_texture(16, 8, 3, Encoding::Srgb, 5);
    ASSERT_EQ(t.levels.size(), 5u);  // 16x8, 8x4, 4x2, 2x1, 1x1
    for (const vec2 uv : {vec2(0.1f, 0.2f), vec2(0.77f, 0.5f), vec2(-1.3f, 2.6f)}) {
        for (const float lod : {0.25f, 1.5f, 2.9f}) {
            const float below = std::floor(lod);
            const glm::vec4 expected = glm::mix(t.sample(uv, below), t.sample(uv, below + 1.0f), lod - below);
            expect_near(t.sample(uv, lod), expected, 1e-6f, "lod " + std::to_string(lod));
        }
    }
}

TEST(Texture, WrapModesHoldAtEveryLevel) {
    Texture t = random_texture(32, 16, 4, Encoding::Srgb, 9);
    for (size_t l = 0; l < t.levels.size(); ++l) {
        const float lod = float(l);
        const Texture::Level& level = t.levels[l];
        // Texel centres of this level.
        for (int i = 0; i < level.width; ++i) {
            const float u = (float(i) + 0.5f) / float(level.width);
            const float v = 0.5f / float(level.height);
            t.wrap_s = t.wrap_t = Wrap::Repeat;
            expect_near(t.sample({u + 3.0f, v - 2.0f}, lod), t.texel(l, i, 0), 1e-5f, "repeat");
            t.wrap_s = t.wrap_t = Wrap::MirroredRepeat;
            expect_near(t.sample({-u, -v}, lod), t.texel(l, i, 0), 1e-5f, "mirrored");
            expect_near(t.sample({2.0f - u, 2.0f + v}, lod), t.texel(l, i, 0), 1e-5f, "mirrored, a period on");
            t.wrap_s = t.wrap_t = Wrap::ClampToEdge;
            expect_near(t.sample({u, -5.0f}, lod), t.texel(l, i, 0), 1e-5f, "clamped above the top row");
        }
        t.wrap_s = t.wrap_t = Wrap::ClampToEdge;
        expect_near(t.sample({7.0f, 9.0f}, lod), t.texel(l, level.width - 1, level.height - 1), 1e-5f, "corner");
    }
}

TEST(Texture, HostileCoordinatesAndLodsStayInside) {
    const Texture t = random_texture(6, 5, 2, Encoding::Srgb, 1);
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    for (const float u : {inf, -inf, nan, 3e38f, -3e38f, 1e9f + 0.5f})
        for (const float lod : {inf, -inf, nan, 1e30f, 2.5f}) {
            const glm::vec4 c = t.sample({u, u}, lod);
            for (int k = 0; k < 4; ++k) {
                EXPECT_GE(c[k], 0.0f);
                EXPECT_LE(c[k], 1.0f);
            }
        }
}

TEST(Texture, EncodingIsRoundTrippedByTheSrgbTable) {
    for (int code = 0; code < 256; ++code) EXPECT_EQ(encode_srgb(srgb_decode_table()[code]), code);
    EXPECT_EQ(encode_srgb(-1.0f), 0);
    EXPECT_EQ(encode_srgb(std::numeric_limits<float>::quiet_NaN()), 0);
    EXPECT_EQ(encode_srgb(2.0f), 255);
}

TEST(Texture, PngRoundTripIsExactForEveryChannelCount) {
    for (int channels = 1; channels <= 4; ++channels) {
        const Texture t = random_texture(7, 5, channels, Encoding::Srgb, uint32_t(channels));
        const std::vector<unsigned char> png = encode_png(t);
        size_t budget = kMaxSceneTextureBytes;
        std::string problem;
        const std::optional<Texture> back = decode_texture(png, "png", Encoding::Srgb, budget, problem);
        ASSERT_TRUE(back) << problem;
        EXPECT_EQ(back->channels, channels);
        ASSERT_EQ(back->levels.size(), t.levels.size());
        for (size_t l = 0; l < t.levels.size(); ++l) EXPECT_EQ(back->levels[l].texels, t.levels[l].texels);
        EXPECT_EQ(budget, kMaxSceneTextureBytes - t.bytes()) << "the budget counts the mips too";
    }
}

TEST(Texture, WebpKeepsUnassociatedAlpha) {
    // Colour under low alpha would not survive a premultiplied decode.
    const Texture t = random_texture(9, 4, 4, Encoding::Srgb, 21);
    uint8_t* webp = nullptr;
    const size_t size = WebPEncodeLosslessRGBA(t.levels[0].texels.data(), 9, 4, 9 * 4, &webp);
    ASSERT_GT(size, 0u);
    const std::vector<unsigned char> bytes(webp, webp + size);
    WebPFree(webp);
    size_t budget = kMaxSceneTextureBytes;
    std::string problem;
    const std::optional<Texture> back = decode_texture(bytes, "webp", Encoding::Srgb, budget, problem);
    ASSERT_TRUE(back) << problem;
    EXPECT_EQ(back->channels, 4);
    EXPECT_EQ(back->levels[0].texels, t.levels[0].texels);
}

TEST(Texture, CostsAtMostFourThirdsOfItsEightBitTexels) {
    for (const auto& [w, h, c] : {std::tuple{1024, 1024, 4}, std::tuple{1000, 600, 3}, std::tuple{4096, 2048, 2},
                                  std::tuple{3, 3, 1}}) {
        const size_t base = size_t(w) * size_t(h) * size_t(c);
        const size_t chain = mip_chain_bytes(w, h, c);
        EXPECT_LE(double(chain), 1.4 * double(base)) << w << "x" << h << "x" << c;
        if (w == 1000) {
            const Texture t = random_texture(w, h, c, Encoding::Srgb, 2);
            EXPECT_EQ(t.bytes(), chain);
            std::printf("a %dx%d RGB texture: %zu bytes with its mips, %.3f of its 8-bit texels (12-byte float "
                        "texels were %zu)\n", w, h, t.bytes(), double(t.bytes()) / double(base),
                        size_t(w) * size_t(h) * 12);
        }
    }
    // A strip halves along one side only once the other reaches 1: up to twice its texels.
    EXPECT_LE(mip_chain_bytes(4096, 1, 1), 2u * 4096u);
}

}  // namespace
}  // namespace rt
