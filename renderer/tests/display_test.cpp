// The display transform: the table encoder gives srgb8's bytes for every kind
// of float, the tone curves' shapes, exposure, and the PNG writer using them.
#include <bit>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "image/display.h"
#include "image/image.h"
#include "loader_test_util.h"

// After protobuf's headers: OpenImageIO's define a bswap_16 that makes
// protobuf's port.h skip its own bswap_32 and bswap_64.
#include <OpenImageIO/imageio.h>

namespace rt {
namespace {

// encode_srgb8 with the default transform against srgb8, value by value.
void expect_srgb8(const std::vector<float>& values) {
    std::vector<float> rgb = values;
    rgb.resize((rgb.size() + 2) / 3 * 3, 0.0f);
    std::vector<uint8_t> bytes(rgb.size());
    encode_srgb8(rgb, DisplayTransform{}, bytes);
    size_t wrong = 0;
    for (size_t i = 0; i < rgb.size(); ++i)
        if (bytes[i] != srgb8(rgb[i]) && ++wrong <= 5)
            ADD_FAILURE() << "encode_srgb8 gives " << int(bytes[i]) << " for " << rgb[i] << " (bits 0x" << std::hex
                          << std::bit_cast<uint32_t>(rgb[i]) << std::dec << "), srgb8 " << int(srgb8(rgb[i]));
    EXPECT_EQ(wrong, 0u);
}

TEST(Display, DefaultEncodingIsSrgb8ForEveryKindOfFloat) {
    // Every 613th float of all 2^32 bit patterns: negatives, NaNs, infinities,
    // subnormals and values above 1 included.
    std::vector<float> sweep;
    for (uint64_t bits = 0; bits < (uint64_t(1) << 32); bits += 613)
        sweep.push_back(std::bit_cast<float>(uint32_t(bits)));
    expect_srgb8(sweep);

    // Every 97th float of [0, 1], where all the codes are.
    sweep.clear();
    for (uint32_t bits = 0; bits <= std::bit_cast<uint32_t>(1.0f); bits += 97)
        sweep.push_back(std::bit_cast<float>(bits));
    expect_srgb8(sweep);

    // Every float within 20000 steps of each code boundary, where rounding
    // decides: the linear value whose sRGB value is (k - 1/2) / 255.
    sweep.clear();
    for (int k = 1; k <= 255; ++k) {
        const double e = (k - 0.5) / 255.0;
        const double linear = e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4);
        const int64_t centre = std::bit_cast<uint32_t>(float(linear));
        for (int64_t bits = centre - 20000; bits <= centre + 20000; ++bits)
            sweep.push_back(std::bit_cast<float>(uint32_t(bits)));
    }
    expect_srgb8(sweep);

    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    expect_srgb8({0.0f, -0.0f, 1.0f, std::nextafter(1.0f, 0.0f), std::nextafter(1.0f, 2.0f), 0.0031308f,
                  std::numeric_limits<float>::denorm_min(), std::numeric_limits<float>::min(),
                  std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(), inf, -inf, nan, -nan,
                  std::numeric_limits<float>::signaling_NaN(), -1.0f, 2.0f, 1e30f});
    EXPECT_EQ(srgb8(nan), 0);
    EXPECT_EQ(srgb8(-nan), 0);
    EXPECT_EQ(srgb8(inf), 255);
    EXPECT_EQ(srgb8(-inf), 0);
}

TEST(Display, RgbaHasOpaqueAlphaAndOtherSizesAreRefused) {
    const std::vector<float> rgb = {0.0f, 0.5f, 1.0f, 0.2f, 2.0f, -1.0f};
    std::vector<uint8_t> rgba(8), plain(6);
    encode_srgb8(rgb, DisplayTransform{}, rgba);
    encode_srgb8(rgb, DisplayTransform{}, plain);
    for (size_t p = 0; p < 2; ++p) {
        for (size_t c = 0; c < 3; ++c) {
            EXPECT_EQ(rgba[4 * p + c], srgb8(rgb[3 * p + c]));
            EXPECT_EQ(plain[3 * p + c], srgb8(rgb[3 * p + c]));
        }
        EXPECT_EQ(rgba[4 * p + 3], 255);
    }
    std::vector<uint8_t> odd(7);
    EXPECT_THROW(encode_srgb8(rgb, DisplayTransform{}, odd), std::invalid_argument);
    EXPECT_THROW(encode_srgb8(std::span<const float>(rgb).first(5), DisplayTransform{}, plain), std::invalid_argument);
}

TEST(Display, ToneCurvesRiseFromZeroTowardsOne) {
    for (const ToneMap curve : {REINHARD, ACES}) {
        EXPECT_EQ(tone_map(vec3(0.0f), curve), vec3(0.0f));
        float previous = 0.0f;
        for (float v = 1e-4f; v < 1e4f; v *= 1.01f) {
            const float mapped = tone_map(vec3(v), curve).x;
            EXPECT_GT(mapped, previous) << v;
            EXPECT_LE(mapped, 1.0f) << v;
            if (mapped >= 1.0f) break;  // ACES's fit reaches 1 and stays
            previous = mapped;
        }
        EXPECT_GT(tone_map(vec3(1e4f), curve).x, 0.999f);
        EXPECT_EQ(srgb8(tone_map(vec3(1e6f), curve).x), 255);
    }
    // Reinhard on luminance: L / (1 + L) for grey, and the hue kept.
    EXPECT_FLOAT_EQ(tone_map(vec3(3.0f), REINHARD).x, 0.75f);
    const vec3 orange = tone_map(vec3(4.0f, 2.0f, 1.0f), REINHARD);
    EXPECT_FLOAT_EQ(orange.y / orange.x, 0.5f);
    EXPECT_FLOAT_EQ(orange.z / orange.x, 0.25f);
    // ACES per channel; negative light is black, the brightest white.
    EXPECT_EQ(tone_map(vec3(-5.0f, 0.5f, 0.5f), ACES).x, 0.0f);
    EXPECT_EQ(tone_map(vec3(1e30f, kInfinity, 7.3f), ACES), vec3(1.0f));
    EXPECT_EQ(tone_map(vec3(std::nanf("")), ACES), vec3(0.0f));
    EXPECT_FLOAT_EQ(tone_map(vec3(-5.0f, 0.5f, 0.5f), ACES).y, tone_map(vec3(0.5f), ACES).y);
    // CLIP leaves the value to the encoding, which clips.
    EXPECT_EQ(tone_map(vec3(7.0f, -1.0f, 0.5f), CLIP), vec3(7.0f, -1.0f, 0.5f));
}

TEST(Display, ExposureScalesBeforeTheCurve) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> value(0.0f, 4.0f);
    std::vector<float> rgb(3000);
    for (float& v : rgb) v = value(rng);
    for (const ToneMap curve : {CLIP, REINHARD, ACES}) {
        for (const float stops : {1.0f, -2.0f, 0.5f}) {
            std::vector<float> scaled = rgb;
            for (float& v : scaled) v *= std::exp2(stops);
            std::vector<uint8_t> exposed(rgb.size()), expected(rgb.size());
            encode_srgb8(rgb, {stops, curve}, exposed);
            encode_srgb8(scaled, {0.0f, curve}, expected);
            EXPECT_EQ(exposed, expected) << "curve " << curve << ", exposure " << stops;
            for (size_t i = 0; i < 300; i += 3) {
                const vec3 mapped = tone_map(vec3(scaled[i], scaled[i + 1], scaled[i + 2]), curve);
                for (int c = 0; c < 3; ++c) EXPECT_EQ(exposed[i + size_t(c)], srgb8(mapped[c]));
            }
        }
    }
}

TEST(Display, TransformComesFromTheSettings) {
    const DisplayTransform defaults = DisplayTransform::from(RenderSettings());
    EXPECT_EQ(defaults.exposure, 0.0f);
    EXPECT_EQ(defaults.tone_map, CLIP);
    RenderSettings settings;
    settings.set_exposure(-1.5f);
    settings.set_tone_map(ACES);
    const DisplayTransform chosen = DisplayTransform::from(settings);
    EXPECT_EQ(chosen.exposure, -1.5f);
    EXPECT_EQ(chosen.tone_map, ACES);
    settings.set_exposure(40.0f);
    EXPECT_THROW(DisplayTransform::from(settings), std::invalid_argument);
}

TEST(Display, PngHoldsTheDisplayTransform) {
    Image image(5, 3);
    for (size_t i = 0; i < image.rgb.size(); ++i) image.rgb[i] = 0.05f * float(i);
    const rt::testing::TempDir dir;
    const DisplayTransform display{1.0f, REINHARD};
    write_image(dir.path() / "shown.png", image, nullptr, display);
    std::vector<uint8_t> expected(image.rgb.size());
    encode_srgb8(image.rgb, display, expected);

    auto in = OIIO::ImageInput::open((dir.path() / "shown.png").string());
    ASSERT_TRUE(in) << OIIO::geterror();
    std::vector<uint8_t> stored(image.rgb.size());
    ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, stored.data()));
    EXPECT_EQ(stored, expected);
}

}  // namespace
}  // namespace rt
