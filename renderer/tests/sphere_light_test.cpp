// Spherical lights: rendered irradiance against the closed form, no bias at one
// shadow ray, convergence under partial occlusion for both light_sampling
// methods, and the light seen by camera and reflection rays.
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "geometry/accel.h"
#include "integrator/render.h"
#include "integrator/sphere_light.h"
#include "test_scenes.h"

namespace rt {
namespace {

using namespace rt::testing;

constexpr float kHeight = 2.0f, kRadius = 0.5f, kIntensity = 3.0f;

// A plane y = 0 whose pixels show irradiance: diffuse albedo pi makes the
// normalized Phong BRDF 1, so outgoing radiance = E. A spherical light above
// it, and a camera under the light looking straight down.
Scene irradiance_scene() {
    Scene scene;
    add_quad(scene, {-20.0f, 0.0f, 20.0f}, {40.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -40.0f},
             add_material(scene, vec3(kPi)));
    add_point_light(scene, {0.0f, kHeight, 0.0f}, kIntensity);
    scene.lights.back().radius = kRadius;
    return scene;
}

const Camera kDown = make_camera({0.0f, 1.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, 70.0f, {0.0f, 0.0f, -1.0f});

std::vector<float> render(const Scene& scene, const Camera& camera, RenderSettings settings) {
    const Accelerator accel(scene, 1);
    const Renderer renderer(accel, settings, camera);
    RenderStats stats;
    return renderer.render(2, 16, nullptr, stats).rgb;
}

RenderSettings light_settings(uint32_t size, LightSampling method, uint32_t light_samples, uint32_t spp = 1) {
    RenderSettings settings = make_settings(size, size);
    settings.set_light_sampling(method);
    settings.set_light_samples(light_samples);
    settings.set_samples_per_pixel(spp);
    return settings;
}

// E at each pixel's centre: the light is wholly above the plane, so E = pi L
// sin^2(theta_max) cos(beta) = pi L (r / D)^2 (h / D) with L = I / (pi r^2),
// which is I h / D^3; under the light, pi L (r / h)^2.
std::vector<float> closed_form(uint32_t size) {
    const ViewCamera pinhole(kDown, size, size);
    std::vector<float> e;
    for (uint32_t y = 0; y < size; ++y) {
        for (uint32_t x = 0; x < size; ++x) {
            const Ray ray = pinhole.generate_ray(float(x) + 0.5f, float(y) + 0.5f);
            const dvec3 p = dvec3(ray.at(-ray.origin.y / ray.direction.y));
            const dvec3 to_light = dvec3(0.0, kHeight, 0.0) - p;
            const double d = glm::length(to_light);
            const double radiance = kIntensity / (kPi * kRadius * kRadius);
            e.push_back(float(kPi * radiance * (kRadius / d) * (kRadius / d) * (to_light.y / d)));
        }
    }
    return e;
}

TEST(SphereLight, IrradianceMatchesTheClosedForm) {
    const Scene scene = irradiance_scene();
    const uint32_t size = 16;
    const std::vector<float> expected = closed_form(size);
    for (LightSampling method : {CONE, SPHERE}) {
        const std::vector<float> image = render(scene, kDown, light_settings(size, method, 1024));
        double worst = 0.0;
        for (size_t p = 0; p < expected.size(); ++p)
            worst = std::max(worst, std::abs(double(image[3 * p]) / expected[p] - 1.0));
        std::printf("%s, 1024 shadow rays: largest irradiance error %.4f%%\n", LightSampling_Name(method).c_str(),
                    100.0 * worst);
        EXPECT_LT(worst, 0.01) << LightSampling_Name(method);
    }
}

// With one or three shadow rays per pixel, the pixels are independent trials of
// the estimator: their mean relative error must be zero within 3 standard errors.
TEST(SphereLight, FewSamplesAreUnbiased) {
    const Scene scene = irradiance_scene();
    const uint32_t size = 64;
    const std::vector<float> expected = closed_form(size);
    for (LightSampling method : {CONE, SPHERE}) {
        for (uint32_t light_samples : {1u, 3u}) {
            const std::vector<float> image = render(scene, kDown, light_settings(size, method, light_samples));
            double sum = 0.0, sum2 = 0.0;
            const double n = double(expected.size());
            for (size_t p = 0; p < expected.size(); ++p) {
                const double error = double(image[3 * p]) / expected[p] - 1.0;
                sum += error;
                sum2 += error * error;
            }
            const double mean = sum / n, standard_error = std::sqrt((sum2 / n - mean * mean) / n);
            std::printf("%s, %u shadow rays: mean relative error %+.5f, standard error %.5f\n",
                        LightSampling_Name(method).c_str(), light_samples, mean, standard_error);
            EXPECT_LT(std::abs(mean), 3.0 * standard_error) << LightSampling_Name(method) << ", " << light_samples;
        }
    }
}

// An opaque sphere between the light and the plane casts a soft shadow: both
// methods converge to the same high-sample image, through camera samples as
// well as shadow rays.
TEST(SphereLight, PartialOcclusionConvergesToTheReference) {
    Scene scene = irradiance_scene();
    scene.spheres.push_back({vec3(0.35f, 1.3f, 0.1f), 0.25f, add_material(scene, vec3(0.5f))});
    const uint32_t size = 24;
    const std::vector<float> reference = render(scene, kDown, light_settings(size, CONE, 4096));
    double mean = 0.0;
    for (size_t p = 0; p < reference.size(); p += 3) mean += reference[p];
    mean /= reference.size() / 3;
    const auto rmse = [&](const std::vector<float>& image) {
        double sum = 0.0;
        for (size_t p = 0; p < reference.size(); p += 3) sum += (image[p] - reference[p]) * (image[p] - reference[p]);
        return std::sqrt(sum / (reference.size() / 3)) / mean;
    };
    // Inside the shadow and out of it, so the test sees a penumbra.
    const float darkest = *std::min_element(reference.begin(), reference.end());
    EXPECT_LT(darkest, 0.5f * mean);
    for (LightSampling method : {CONE, SPHERE}) {
        double previous = INFINITY;
        for (uint32_t light_samples : {4u, 16u, 64u, 256u}) {
            const double error = rmse(render(scene, kDown, light_settings(size, method, light_samples)));
            std::printf("%s, %u shadow rays: relative RMSE %.5f\n", LightSampling_Name(method).c_str(),
                        light_samples, error);
            EXPECT_LT(error, previous) << LightSampling_Name(method) << ", " << light_samples;
            previous = error;
        }
        // SPHERE spends half its rays on the far side, and the rest see the
        // sphere at every angle: about 4 times CONE's error at equal count.
        EXPECT_LT(previous, method == CONE ? 0.01 : 0.03) << LightSampling_Name(method);
    }
    // SPHERE wastes the far side's rays but converges to the same image.
    EXPECT_LT(rmse(render(scene, kDown, light_settings(size, SPHERE, 4096))), 0.004);
    // With one shadow ray per camera sample, the pixel's 256 samples stratify
    // the light between them: the error is that of 256 rays at one sample
    // (the film's spread over the pixel (BOX) adds its own, smaller change).
    RenderSettings settings = light_settings(size, CONE, 1, 256);
    settings.set_pixel_filter(BOX);
    const double spread = rmse(render(scene, kDown, settings));
    std::printf("CONE, 256 samples per pixel x 1 shadow ray: relative RMSE %.5f\n", spread);
    EXPECT_LT(spread, 0.02);
}

TEST(SphereLight, CameraAndReflectionRaysSeeTheLight) {
    Scene scene;
    add_quad(scene, {-5.0f, -5.0f, -3.0f}, {10.0f, 0.0f, 0.0f}, {0.0f, 10.0f, 0.0f},
             add_material(scene, vec3(0.0f), vec3(0.0f), 1.0f, vec3(0.5f)));  // a half-silvered mirror at z = -3
    add_point_light(scene, {0.0f, 0.0f, -1.0f}, 2.0f);
    scene.lights.back().radius = 0.25f;
    const Accelerator accel(scene, 1);
    const vec3 radiance = sphere_light_radiance(scene.lights[0]);
    EXPECT_NEAR(radiance.x, 2.0f / (kPi * 0.0625f), 1e-5f);
    // Looking at the light from (0, 0, 1): the centre pixel sees it directly.
    const Renderer front(accel, make_settings(9, 9), make_camera({0.0f, 0.0f, 1.0f}, {0.0f, 0.0f, -1.0f}, 10.0f));
    float rgb[3];
    front.render_tile({4, 4, 1, 1}, rgb);
    EXPECT_EQ(vec3(rgb[0], rgb[1], rgb[2]), radiance);
    const DebugPath path = front.debug_pixel(4, 4);
    ASSERT_EQ(path.segments_size(), 1);
    EXPECT_EQ(path.segments(0).outcome(), REACHED_LIGHT);
    EXPECT_NEAR(path.segments(0).t(), 1.75f, 1e-5f);
    // From beside it, looking at the mirror: the light's reflection, at half its radiance.
    const Renderer mirror(accel, make_settings(9, 9), make_camera({0.0f, 0.0f, -2.0f}, {0.0f, 0.0f, -3.0f}, 10.0f));
    mirror.render_tile({4, 4, 1, 1}, rgb);
    EXPECT_NEAR(rgb[0], 0.5f * radiance.x, 1e-4f * radiance.x);
}

}  // namespace
}  // namespace rt
