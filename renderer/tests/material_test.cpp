// Texture sampling: bilinear filtering with texel centres at half-integers, the
// three glTF wrap modes, and robustness to coordinates no file should contain.
#include "geometry/material.h"

#include <limits>

#include <gtest/gtest.h>

#include "load/texture_decode.h"

namespace rt {
namespace {

// A 4x1 linear grey ramp: texel i holds i / 3, which at() scales back to i.
Texture ramp(Texture::Wrap wrap) {
    Texture t(4, 1, 1, Texture::Encoding::Linear, {0, 85, 170, 255});
    t.wrap_s = t.wrap_t = wrap;
    return t;
}

float at(const Texture& t, float u) { return 3.0f * t.sample({u, 0.5f}).x; }

TEST(MaterialTexture, TexelCentresSitAtHalfIntegers) {
    const Texture t = ramp(Texture::Wrap::ClampToEdge);
    for (int i = 0; i < 4; ++i) EXPECT_FLOAT_EQ(at(t, (i + 0.5f) / 4.0f), float(i));
    EXPECT_FLOAT_EQ(at(t, 0.25f), 0.5f);    // between texels 0 and 1
    EXPECT_FLOAT_EQ(at(t, 0.3125f), 0.75f);  // three quarters of the way from texel 0 to 1
}

TEST(MaterialTexture, BilinearInBothDirections) {
    Texture t(2, 2, 1, Texture::Encoding::Linear, {0, 85, 170, 255});  // rows: (0 1) over (2 3), in thirds
    t.wrap_s = t.wrap_t = Texture::Wrap::ClampToEdge;
    const auto at2 = [&](vec2 uv) { return 3.0f * t.sample(uv).x; };
    EXPECT_FLOAT_EQ(at2({0.5f, 0.5f}), 1.5f);
    EXPECT_FLOAT_EQ(at2({0.25f, 0.5f}), 1.0f);   // between rows, in column 0
    EXPECT_FLOAT_EQ(at2({0.75f, 0.25f}), 1.0f);  // row 0 (v = 0 is the top), column 1
    EXPECT_FLOAT_EQ(at2({0.625f, 0.375f}), 1.25f);  // rows give 0.75 and 2.75, a quarter apart
}

TEST(MaterialTexture, RepeatWrapsAcrossTheEdge) {
    const Texture t = ramp(Texture::Wrap::Repeat);
    EXPECT_FLOAT_EQ(at(t, 0.0f), 1.5f);  // half texel 3, half texel 0
    EXPECT_FLOAT_EQ(at(t, 1.125f), 0.0f);
    EXPECT_FLOAT_EQ(at(t, -0.875f), 0.0f);
    EXPECT_FLOAT_EQ(at(t, 7.375f), 1.0f);
}

TEST(MaterialTexture, ClampToEdgeHoldsTheEdgeTexel) {
    const Texture t = ramp(Texture::Wrap::ClampToEdge);
    EXPECT_FLOAT_EQ(at(t, 0.0f), 0.0f);
    EXPECT_FLOAT_EQ(at(t, -3.0f), 0.0f);
    EXPECT_FLOAT_EQ(at(t, 1.0f), 3.0f);
    EXPECT_FLOAT_EQ(at(t, 42.0f), 3.0f);
}

TEST(MaterialTexture, MirroredRepeatReflectsAtEachEdge) {
    const Texture t = ramp(Texture::Wrap::MirroredRepeat);
    EXPECT_FLOAT_EQ(at(t, 0.0f), 0.0f);       // the mirror repeats texel 0
    EXPECT_FLOAT_EQ(at(t, 1.0f), 3.0f);       // and texel 3
    EXPECT_FLOAT_EQ(at(t, 1.125f), 3.0f);     // first texel past the edge: 3 again
    EXPECT_FLOAT_EQ(at(t, 1.375f), 2.0f);
    EXPECT_FLOAT_EQ(at(t, -0.125f), 0.0f);
    EXPECT_FLOAT_EQ(at(t, -0.375f), 1.0f);
    EXPECT_FLOAT_EQ(at(t, 2.125f), 0.0f);     // a full period later: as at 0.125
}

TEST(MaterialTexture, HostileCoordinatesStayInsideTheImage) {
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    for (Texture::Wrap wrap : {Texture::Wrap::Repeat, Texture::Wrap::ClampToEdge, Texture::Wrap::MirroredRepeat}) {
        const Texture t = ramp(wrap);
        for (float u : {inf, -inf, nan, 3e38f, -3e38f, 1e9f + 0.5f, -1e-30f}) {
            const float v = at(t, u);
            EXPECT_GE(v, 0.0f) << u;
            EXPECT_LE(v, 3.0f) << u;
        }
    }
    EXPECT_EQ(Texture().sample({0.5f, 0.5f}), glm::vec4(1.0f));  // an empty texture leaves the colour alone
}

TEST(MaterialTexture, SrgbDecodingMatchesTheStandard) {
    EXPECT_FLOAT_EQ(srgb_to_linear(0.0f), 0.0f);
    EXPECT_FLOAT_EQ(srgb_to_linear(1.0f), 1.0f);
    EXPECT_NEAR(srgb_to_linear(0.04045f), 0.04045f / 12.92f, 1e-7f);  // the linear segment
    EXPECT_NEAR(srgb_to_linear(0.5f), 0.2140411f, 1e-6f);
}

}  // namespace
}  // namespace rt
