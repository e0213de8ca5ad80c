// Ray-cone texture filtering against moiré: a checkerboard ground plane seen
// at a grazing angle towards the horizon, one sample per pixel, filtered and
// not, each compared with a 16x16 supersampled render that reads level 0 only.
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "geometry/accel.h"
#include "integrator/camera.h"
#include "integrator/whitted.h"
#include "test_scenes.h"

namespace rt {
namespace {

using namespace rt::testing;

constexpr uint32_t kWidth = 160, kHeight = 96;
constexpr float kHalfSize = 4000.0f;  // the plane reaches this far each way
constexpr float kSquare = 1.0f;       // world units per checker square
const Camera kCamera = make_camera({0.0f, 1.0f, 0.0f}, {0.0f, 1.0f - std::tan(0.17f), -1.0f}, 45.0f);

// 256x256 sRGB texels of 8x8 black and white squares, repeated every 8 units.
Texture checker() {
    std::vector<uint8_t> texels(256 * 256);
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x) texels[size_t(y) * 256 + size_t(x)] = ((x / 32 + y / 32) % 2) ? 255 : 0;
    return Texture(256, 256, 1, Texture::Encoding::Srgb, std::move(texels));
}

// Lit straight from above by a sun of pi lux, the Lambertian plane sends back
// exactly its texel: radiance is the texture in linear light.
Scene checker_plane() {
    Scene scene;
    const uint32_t m = add_material(scene, vec3(1.0f));
    add_quad(scene, {-kHalfSize, 0.0f, kHalfSize}, {2.0f * kHalfSize, 0.0f, 0.0f}, {0.0f, 0.0f, -2.0f * kHalfSize}, m);
    for (const vec3& p : scene.positions) scene.texcoords.push_back(vec2(p.x, p.z) / (8.0f * kSquare));
    scene.textures.push_back(checker());
    scene.materials[m].base_color_texture.index = 0;
    Light sun;
    sun.kind = DIRECTIONAL;
    sun.direction = {0.0f, -1.0f, 0.0f};
    sun.intensity = vec3(kPi);
    scene.lights.push_back(sun);
    return scene;
}

TEST(TextureFilter, RayConesRemoveTheFarFieldsMoire) {
    const Scene scene = checker_plane();
    const Accelerator accel(scene, 1);
    RenderSettings settings = make_settings(kWidth, kHeight);
    settings.set_max_depth(0);
    const WhittedIntegrator integrator(accel, settings);
    const ViewCamera pinhole(kCamera, kWidth, kHeight);
    const RayCone cone = pinhole.ray_cone();
    RayCounts rays;

    // The far field: pixels whose centre ray meets the plane beyond 20 squares.
    double filtered_error = 0.0, unfiltered_error = 0.0, filtered_sum = 0.0, reference_sum = 0.0;
    size_t far = 0;
    for (uint32_t y = 0; y < kHeight; ++y) {
        for (uint32_t x = 0; x < kWidth; ++x) {
            const Ray centre = pinhole.generate_ray(float(x) + 0.5f, float(y) + 0.5f);
            const float t = centre.direction.y < 0.0f ? -centre.origin.y / centre.direction.y : kInfinity;
            if (!(t > 20.0f * kSquare) || std::abs(centre.at(t).z) > 0.9f * kHalfSize) continue;
            double reference = 0.0;
            for (int j = 0; j < 16; ++j)
                for (int i = 0; i < 16; ++i) {
                    const Ray ray = pinhole.generate_ray(float(x) + (float(i) + 0.5f) / 16.0f,
                                                         float(y) + (float(j) + 0.5f) / 16.0f);
                    reference += integrator.radiance(ray, PixelSampler(0, 0), rays).g;  // no cone: level 0
                }
            reference /= 256.0;
            const double filtered = integrator.radiance(centre, PixelSampler(0, 0), rays, cone).g;
            const double unfiltered = integrator.radiance(centre, PixelSampler(0, 0), rays).g;
            filtered_error += (filtered - reference) * (filtered - reference);
            unfiltered_error += (unfiltered - reference) * (unfiltered - reference);
            filtered_sum += filtered;
            reference_sum += reference;
            ++far;
        }
    }
    ASSERT_GT(far, 1000u);
    const double filtered_rmse = std::sqrt(filtered_error / double(far));
    const double unfiltered_rmse = std::sqrt(unfiltered_error / double(far));
    const double filtered_mean = filtered_sum / double(far), reference_mean = reference_sum / double(far);
    std::printf("far field (%zu pixels) against 16x16 supersampling: RMSE %.4f filtered, %.4f unfiltered; "
                "mean %.4f filtered, %.4f reference (linear grey 0.5)\n",
                far, filtered_rmse, unfiltered_rmse, filtered_mean, reference_mean);
    EXPECT_LT(filtered_rmse, 0.5 * unfiltered_rmse);
    EXPECT_NEAR(filtered_mean, 0.5, 0.03) << "the checker's linear grey, not its sRGB mean 0.21";
    EXPECT_NEAR(reference_mean, 0.5, 0.03);
}

TEST(TextureFilter, NearTexelsStaySharp) {
    // Close up and facing the plane, a pixel covers well under a texel: the
    // cone reads level 0, exactly as an unfiltered lookup does.
    const Scene scene = checker_plane();
    const Accelerator accel(scene, 1);
    const Camera down = make_camera({0.3f, 0.5f, 0.2f}, {0.3f, 0.0f, 0.2f}, 45.0f, {0.0f, 0.0f, -1.0f});
    RenderSettings settings = make_settings(64, 64);
    settings.set_max_depth(0);
    const WhittedIntegrator integrator(accel, settings);
    const ViewCamera pinhole(down, 64, 64);
    RayCounts rays;
    for (uint32_t y = 0; y < 64; y += 7)
        for (uint32_t x = 0; x < 64; x += 5) {
            const Ray ray = pinhole.generate_ray(float(x) + 0.5f, float(y) + 0.5f);
            EXPECT_EQ(integrator.radiance(ray, PixelSampler(0, 0), rays, pinhole.ray_cone()),
                      integrator.radiance(ray, PixelSampler(0, 0), rays));
        }
}

}  // namespace
}  // namespace rt
