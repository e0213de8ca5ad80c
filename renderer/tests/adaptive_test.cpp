// Adaptive sampling: pixels stop in whole batches once their error estimate is
// small, the counts add up, and on the Cornell box with a spherical light it
// reaches uniform sampling's error with fewer samples.
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "geometry/accel.h"
#include "integrator/render.h"
#include "test_meshes.h"
#include "test_scenes.h"

namespace rt {
namespace {

using namespace rt::testing;

constexpr uint32_t kWidth = 32, kHeight = 24;

RenderSettings cornell_settings(uint32_t spp, float threshold) {
    RenderSettings settings = make_settings(kWidth, kHeight);
    settings.set_samples_per_pixel(spp);
    settings.set_adaptive_threshold(threshold);
    settings.set_light_samples(1);  // each camera sample also samples the light once
    return settings;
}

double rmse(const std::vector<float>& image, const std::vector<float>& reference) {
    double sum = 0.0;
    for (size_t i = 0; i < image.size(); ++i) sum += (image[i] - reference[i]) * (image[i] - reference[i]);
    return std::sqrt(sum / double(image.size()));
}

// Uniform sampling's RMSE at 32 to 256 samples per pixel, fitted as a power of
// N, says how many uniform samples adaptive sampling's RMSE would have cost.
// (In linear RMSE the pixels on the light's outline, radiance 64 against the
// ceiling's 0.8, weigh most: they are where adaptive sampling spends.)
TEST(Adaptive, FewerSamplesForTheSameErrorOnTheCornellBox) {
    const Scene scene = sample_scene("cornell_sphere_light.obj");
    const Accelerator accel(scene);
    const Camera& camera = scene.cameras.front().camera;
    const auto render = [&](const RenderSettings& settings, double& mean_samples) {
        RenderStats stats;
        const std::vector<float> rgb = Renderer(accel, settings, camera).render(2, 16, nullptr, stats).rgb;
        mean_samples = double(stats.samples) / (kWidth * kHeight);
        return rgb;
    };
    double spp = 0.0;
    const std::vector<float> reference = render(cornell_settings(2048, 0.0f), spp);

    double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
    for (uint32_t n : {32u, 64u, 128u, 256u}) {
        const double error = rmse(render(cornell_settings(n, 0.0f), spp), reference);
        EXPECT_EQ(spp, double(n));
        std::printf("uniform %3u samples/pixel: RMSE %.4f\n", n, error);
        const double x = std::log(double(n)), y = std::log(error);
        sx += x, sy += y, sxx += x * x, sxy += x * y;
    }
    const double slope = (4.0 * sxy - sx * sy) / (4.0 * sxx - sx * sx), intercept = (sy - slope * sx) / 4.0;

    double adaptive_spp = 0.0;
    const double adaptive_error = rmse(render(cornell_settings(256, 0.02f), adaptive_spp), reference);
    const double uniform_spp = std::exp((std::log(adaptive_error) - intercept) / slope);
    std::printf("adaptive (threshold 0.02, at most 256): %.1f samples/pixel, RMSE %.4f; uniform sampling needs "
                "%.1f samples/pixel for that RMSE (fitted slope %.3f)\n",
                adaptive_spp, adaptive_error, uniform_spp, slope);
    EXPECT_LT(adaptive_spp, 256.0);
    EXPECT_LT(adaptive_spp, uniform_spp);
}

TEST(Adaptive, TheMinimumGrowsAsTheThresholdTightens) {
    EXPECT_EQ(StoppingRule(1.0f, 1024).min_samples(), 16u);
    EXPECT_EQ(StoppingRule(0.2f, 1024).min_samples(), 32u);    // 16 / 0.2^0.3 = 25.9
    EXPECT_EQ(StoppingRule(0.02f, 1024).min_samples(), 64u);   // 51.8
    EXPECT_EQ(StoppingRule(0.001f, 1024).min_samples(), 128u); // 126.8
    EXPECT_EQ(StoppingRule(0.02f, 40).min_samples(), 40u);     // never above samples_per_pixel
}

// Each pixel takes the minimum and then whole batches of 8, at most
// samples_per_pixel; a tile's count is the sum over its pixels; flat pixels
// stop at the minimum and noisy ones take more.
TEST(Adaptive, PixelsStopInWholeBatchesAndTheCountsAddUp) {
    const Scene scene = sample_scene("cornell_sphere_light.obj");
    const Accelerator accel(scene);
    const Renderer renderer(accel, cornell_settings(128, 0.2f), scene.cameras.front().camera);
    std::vector<float> rgb(size_t(kWidth) * kHeight * 3);
    const RenderStats tile = renderer.render_tile({0, 0, kWidth, kHeight}, rgb.data());
    uint64_t sum = 0;
    int at_minimum = 0, more = 0;
    for (uint32_t y = 0; y < kHeight; ++y) {
        for (uint32_t x = 0; x < kWidth; ++x) {
            float pixel[3];
            const uint64_t samples = renderer.render_tile({x, y, 1, 1}, pixel).samples;
            EXPECT_EQ(samples % 8, 0u);
            EXPECT_GE(samples, 32u);
            EXPECT_LE(samples, 128u);
            at_minimum += samples == 32;
            more += samples > 32;
            sum += samples;
        }
    }
    EXPECT_EQ(tile.samples, sum);
    EXPECT_GT(at_minimum, 0);
    EXPECT_GT(more, 0);
}

}  // namespace
}  // namespace rt
