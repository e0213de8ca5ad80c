// Bloom: what it leaves alone, that it moves light without adding any (borders
// included), and that the glow is the Gaussian the settings name.
#include <cmath>
#include <cstring>
#include <random>

#include <gtest/gtest.h>

#include "image/bloom.h"

namespace rt {
namespace {

RenderSettings bloom_settings(float threshold, float radius, float strength) {
    RenderSettings settings;
    settings.set_bloom_threshold(threshold);
    settings.set_bloom_radius(radius);
    settings.set_bloom_strength(strength);
    return settings;
}

void set_pixel(Image& image, uint32_t x, uint32_t y, vec3 value) {
    for (int c = 0; c < 3; ++c) image.rgb[(size_t(y) * image.width + x) * 3 + size_t(c)] = value[c];
}

// Random light below `peak` per channel.
Image random_image(uint32_t w, uint32_t h, float peak, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> value(0.0f, peak);
    Image image(w, h);
    for (float& v : image.rgb) v = value(rng);
    return image;
}

dvec3 sum(const Image& image) {
    dvec3 total(0.0);
    for (size_t i = 0; i < image.rgb.size(); ++i) total[int(i % 3)] += image.rgb[i];
    return total;
}

bool same_bytes(const Image& a, const Image& b) {
    return a.rgb.size() == b.rgb.size() && std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

TEST(Bloom, NothingAboveTheThresholdLeavesTheImageUnchanged) {
    Image image = random_image(64, 48, 0.99f, 1);  // luminance below 0.99
    const Image before = image;
    apply_bloom(image, bloom_settings(1.0f, 10.0f, 1.0f));
    EXPECT_TRUE(same_bytes(image, before));
}

TEST(Bloom, StrengthZeroLeavesTheImageUnchanged) {
    Image image = random_image(64, 48, 20.0f, 2);
    const Image before = image;
    apply_bloom(image, bloom_settings(1.0f, 10.0f, 0.0f));
    EXPECT_TRUE(same_bytes(image, before));
    apply_bloom(image, RenderSettings());  // the default strength is 0
    EXPECT_TRUE(same_bytes(image, before));
}

// Light is moved, never added or lost: wherever the bright pixels are, the
// corners and edges, whose glow would partly fall outside, included.
class BloomEnergy : public ::testing::TestWithParam<float> {};

TEST_P(BloomEnergy, TheImageSumIsUnchanged) {
    const float strength = GetParam();
    const uint32_t w = 97, h = 61;
    struct Case {
        const char* name;
        std::vector<std::pair<uint32_t, uint32_t>> bright;
        float radius;
    };
    const Case cases[] = {
        {"corner", {{0, 0}}, 10.0f},
        {"far corner", {{w - 1, h - 1}}, 25.0f},
        {"middle", {{w / 2, h / 2}}, 10.0f},
        {"edge", {{w / 2, 0}, {0, h / 3}}, 10.0f},
        {"wider than the image", {{3, 5}, {w - 2, h - 4}}, 200.0f},
    };
    for (const Case& test : cases) {
        Image image = random_image(w, h, 0.5f, 3);
        for (const auto& [x, y] : test.bright) set_pixel(image, x, y, vec3(40.0f, 25.0f, 10.0f));
        const dvec3 before = sum(image);
        const Image original = image;
        apply_bloom(image, bloom_settings(1.0f, test.radius, strength));
        EXPECT_FALSE(same_bytes(image, original)) << test.name;
        const dvec3 after = sum(image);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(after[c], before[c], 1e-5 * before[c]) << test.name << " channel " << c;
    }

    // Many bright pixels of every kind of colour.
    Image image = random_image(256, 200, 3.0f, 4);
    const dvec3 before = sum(image);
    apply_bloom(image, bloom_settings(1.0f, 10.0f, strength));
    const dvec3 after = sum(image);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(after[c], before[c], 1e-5 * before[c]) << "channel " << c;
}

INSTANTIATE_TEST_SUITE_P(Strengths, BloomEnergy, ::testing::Values(1.0f, 0.5f));

// The glow of one pixel on black, all of it spread (threshold 0, strength 1).
Image glow_of_one_pixel(uint32_t size, float radius, vec3 value) {
    Image image(size, size);
    set_pixel(image, size / 2, size / 2, value);
    apply_bloom(image, bloom_settings(0.0f, radius, 1.0f));
    return image;
}

TEST(Bloom, TheGlowIsAGaussianOfStandardDeviationRadiusOverThree) {
    for (const float radius : {3.0f, 10.0f, 30.0f}) {
        const uint32_t size = 201, centre = size / 2;
        const Image glow = glow_of_one_pixel(size, radius, vec3(1.0f));
        double total = 0.0, mean_x = 0.0, mean_y = 0.0, var_x = 0.0, var_y = 0.0;
        for (uint32_t y = 0; y < size; ++y)
            for (uint32_t x = 0; x < size; ++x) {
                const double v = glow.pixel(x, y).x, dx = double(x) - centre, dy = double(y) - centre;
                total += v;
                mean_x += v * dx;
                mean_y += v * dy;
                var_x += v * dx * dx;
                var_y += v * dy * dy;
            }
        const double sigma = radius / 3.0;
        EXPECT_NEAR(total, 1.0, 1e-5);
        EXPECT_NEAR(mean_x / total, 0.0, 1e-4);
        EXPECT_NEAR(mean_y / total, 0.0, 1e-4);
        EXPECT_NEAR(var_x / total, sigma * sigma, 0.02 * sigma * sigma) << "radius " << radius;
        EXPECT_NEAR(var_y / total, sigma * sigma, 0.02 * sigma * sigma) << "radius " << radius;
    }
}

TEST(Bloom, TheGlowIsSeparableAndSymmetric) {
    const uint32_t size = 81, c = size / 2;
    const Image glow = glow_of_one_pixel(size, 12.0f, vec3(1.0f));
    const double g11 = glow.pixel(c + 1, c + 1).x;
    for (uint32_t d = 0; d <= 16; ++d)
        for (uint32_t e = 0; e <= 16; ++e) {
            const float v = glow.pixel(c + d, c + e).x;
            // Mirror images and the transpose: one kernel, both axes.
            EXPECT_FLOAT_EQ(glow.pixel(c - d, c + e).x, v);
            EXPECT_FLOAT_EQ(glow.pixel(c + d, c - e).x, v);
            EXPECT_FLOAT_EQ(glow.pixel(c + e, c + d).x, v);
            // A product of a function of x and one of y: g(d, e) g(1, 1) = g(d, 1) g(1, e).
            // (Not through the centre, which also gives up its own light.)
            if (d == 0 || e == 0) continue;
            const double product = double(glow.pixel(c + d, c + 1).x) * glow.pixel(c + 1, c + e).x;
            EXPECT_NEAR(v * g11, product, 1e-5 * product) << d << "," << e;
        }
}

TEST(Bloom, OnlyTheLightAboveTheThresholdSpreadsAndKeepsItsHue) {
    const uint32_t size = 81, c = size / 2;
    const vec3 value(8.0f, 4.0f, 2.0f);
    const float l = luminance(value), threshold = 1.5f, strength = 0.75f;
    Image image(size, size);
    set_pixel(image, c, c, value);
    apply_bloom(image, bloom_settings(threshold, 9.0f, strength));

    const vec3 spread = strength * value * ((l - threshold) / l);
    const vec3 total = vec3(sum(image));
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(total[k], value[k], 1e-5f * value[k]);
    // What left the centre is what arrived elsewhere, in the pixel's hue.
    vec3 elsewhere = total - image.pixel(c, c);
    const vec3 neighbour = image.pixel(c + 2, c - 1);
    for (int k = 0; k < 3; ++k) {
        EXPECT_LT(elsewhere[k], spread[k]);
        EXPECT_GT(elsewhere[k], 0.9f * spread[k]);
        EXPECT_NEAR(neighbour[k] / neighbour.x, value[k] / value.x, 1e-5f);
    }
}

TEST(Bloom, PixelsThatAreNotFiniteAreNotSpread) {
    Image image = random_image(40, 30, 2.0f, 5);
    set_pixel(image, 10, 10, vec3(kInfinity, 1.0f, 1.0f));
    set_pixel(image, 30, 20, vec3(std::nanf(""), 5.0f, 5.0f));
    apply_bloom(image, bloom_settings(1.0f, 10.0f, 1.0f));
    EXPECT_EQ(image.pixel(10, 10).x, kInfinity);
    EXPECT_TRUE(std::isnan(image.pixel(30, 20).x));
    for (uint32_t y = 0; y < 30; ++y) {
        for (uint32_t x = 0; x < 40; ++x) {
            if ((x == 10 && y == 10) || (x == 30 && y == 20)) continue;
            EXPECT_TRUE(is_finite(image.pixel(x, y))) << x << "," << y;
        }
    }
}

TEST(Bloom, SettingsOutsideTheirLimitsAreRefused) {
    Image image = random_image(8, 8, 4.0f, 6);
    EXPECT_THROW(apply_bloom(image, bloom_settings(1.0f, 10.0f, 1.5f)), std::invalid_argument);
    EXPECT_THROW(apply_bloom(image, bloom_settings(1.0f, 0.0f, 1.0f)), std::invalid_argument);
}

}  // namespace
}  // namespace rt
