// Anti-aliasing: a pixel's error against its exact coverage falls with the
// sample count at least as fast as 1/sqrt(N), and faster than with independent
// random samples; GRID is the 2020 report's supersampling; one sample is the pixel's
// centre whatever the filter, as before there were filters.
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "geometry/accel.h"
#include "integrator/render.h"
#include "test_scenes.h"

namespace rt {
namespace {

using namespace rt::testing;

constexpr uint32_t kSize = 48;
// The edge runs through these film points (pixel units), black to its right.
constexpr vec2 kEdgeTop(14.3f, -8.0f), kEdgeBottom(34.1f, 56.0f);

const Camera kCamera = make_camera(vec3(0.0f), {0.0f, 0.0f, -1.0f}, 60.0f);

// Where the camera's ray through film point f meets the plane z = -1.
vec3 on_plane(vec2 f) {
    const Ray ray = ViewCamera(kCamera, kSize, kSize).generate_ray(f.x, f.y);
    return ray.at(-1.0f / ray.direction.z);
}

// A black parallelogram in front of a white background, its left edge the
// line through kEdgeTop and kEdgeBottom in the image: the plane is parallel to
// the film, so the film-to-plane map is affine and keeps the edge straight.
Scene edge_scene() {
    Scene scene;
    scene.background = vec3(1.0f);
    const vec3 top = on_plane(kEdgeTop);
    add_quad(scene, top, on_plane(kEdgeBottom) - top, on_plane(kEdgeTop + vec2(100.0f, 0.0f)) - top,
             add_material(scene, vec3(0.0f)));
    return scene;
}

// The share of pixel (x, y) left of the edge: the unit square clipped by the
// edge's half-plane (Sutherland-Hodgman), its area by the shoelace formula.
double uncovered(uint32_t x, uint32_t y) {
    const dvec3 a(kEdgeTop.x, kEdgeTop.y, 0.0), b(kEdgeBottom.x, kEdgeBottom.y, 0.0);
    const auto side = [&](const glm::dvec2& p) { return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x); };
    const std::vector<glm::dvec2> square = {{x, y}, {x + 1.0, y}, {x + 1.0, y + 1.0}, {x, y + 1.0}};
    std::vector<glm::dvec2> kept;
    for (size_t i = 0; i < square.size(); ++i) {
        const glm::dvec2 p = square[i], q = square[(i + 1) % square.size()];
        const double sp = side(p), sq = side(q);
        if (sp >= 0.0) kept.push_back(p);
        if ((sp >= 0.0) != (sq >= 0.0)) kept.push_back(p + (q - p) * (sp / (sp - sq)));
    }
    double area = 0.0;
    for (size_t i = 0; i < kept.size(); ++i) {
        const glm::dvec2 p = kept[i], q = kept[(i + 1) % kept.size()];
        area += p.x * q.y - q.x * p.y;
    }
    return std::abs(area) / 2.0;
}

double rmse(const std::vector<float>& rgb) {
    double sum = 0.0;
    for (uint32_t y = 0; y < kSize; ++y) {
        for (uint32_t x = 0; x < kSize; ++x) {
            const double e = rgb[3 * (size_t(y) * kSize + x)] - uncovered(x, y);
            sum += e * e;
        }
    }
    return std::sqrt(sum / (kSize * kSize));
}

// Least-squares slope of log(error) over log(N).
double slope(const std::vector<double>& n, const std::vector<double>& error) {
    double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
    for (size_t i = 0; i < n.size(); ++i) {
        const double x = std::log(n[i]), y = std::log(error[i]);
        sx += x, sy += y, sxx += x * x, sxy += x * y;
    }
    const double k = double(n.size());
    return (k * sxy - sx * sy) / (k * sxx - sx * sx);
}

TEST(AntiAliasing, EdgeErrorFallsFasterThanWithIndependentSamples) {
    const Scene scene = edge_scene();
    const Accelerator accel(scene, 1);
    RenderSettings settings = make_settings(kSize, kSize);
    settings.set_pixel_filter(BOX);
    const WhittedIntegrator integrator(accel, settings);
    const ViewCamera pinhole(kCamera, kSize, kSize);
    std::mt19937 random(7);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);

    const std::vector<double> counts = {4, 16, 64, 256};
    std::vector<double> stratified, independent;
    for (double n : counts) {
        settings.set_samples_per_pixel(uint32_t(n));
        const Renderer renderer(accel, settings, kCamera);
        RenderStats stats;
        stratified.push_back(rmse(renderer.render(2, 16, nullptr, stats).rgb));
        EXPECT_EQ(stats.samples, uint64_t(n) * kSize * kSize);

        // The same pixels from independent uniform offsets: what stratification beats.
        std::vector<float> rgb(size_t(kSize) * kSize * 3);
        RayCounts rays;
        for (uint32_t y = 0; y < kSize; ++y) {
            for (uint32_t x = 0; x < kSize; ++x) {
                double sum = 0.0;
                for (uint32_t i = 0; i < uint32_t(n); ++i) {
                    const Ray ray = pinhole.generate_ray(float(x) + uniform(random), float(y) + uniform(random));
                    sum += integrator.radiance(ray, PixelSampler(0, i), rays).r;
                }
                rgb[3 * (size_t(y) * kSize + x)] = float(sum / n);
            }
        }
        independent.push_back(rmse(rgb));
        std::printf("N = %3.0f: RMSE stratified %.5f, independent %.5f\n", n, stratified.back(), independent.back());
        EXPECT_LT(stratified.back(), independent.back()) << n << " samples";
    }
    const double stratified_slope = slope(counts, stratified), independent_slope = slope(counts, independent);
    std::printf("fitted slope of log RMSE over log N: stratified %.3f, independent %.3f\n", stratified_slope,
                independent_slope);
    EXPECT_LT(stratified_slope, -0.5);
}

// GRID with 4 samples is the 2020 report's supersampling: the image rendered at twice
// the resolution, each 2 x 2 block averaged; likewise 16 samples and 4 times.
TEST(AntiAliasing, GridIsSupersamplingAtAHigherResolution) {
    const Scene scene = floor_and_sphere(1.0f);
    const Accelerator accel(scene, 1);
    const Camera camera = make_camera({0.0f, 3.0f, 9.0f}, {0.0f, 0.8f, 0.0f}, 40.0f);
    const uint32_t w = 20, h = 14;
    for (uint32_t k : {2u, 4u}) {
        RenderSettings settings = make_settings(w, h);
        settings.set_pixel_filter(GRID);
        settings.set_samples_per_pixel(k * k);
        RenderStats stats;
        const Image grid = Renderer(accel, settings, camera).render(1, 8, nullptr, stats);
        const Image fine = Renderer(accel, make_settings(k * w, k * h), camera).render(1, 8, nullptr, stats);
        int differing = 0;
        for (uint32_t y = 0; y < h; ++y) {
            for (uint32_t x = 0; x < w; ++x) {
                dvec3 sum(0.0);
                for (uint32_t j = 0; j < k; ++j)
                    for (uint32_t i = 0; i < k; ++i) sum += dvec3(fine.pixel(k * x + i, k * y + j));
                differing += grid.pixel(x, y) != vec3(sum / double(k * k));
            }
        }
        EXPECT_EQ(differing, 0) << k << " x " << k;
    }
}

// Default settings: one sample through each pixel's centre, the image of
// before samples_per_pixel existed, whatever filter is named.
TEST(AntiAliasing, OneSampleIsThePixelCentreWhateverTheFilter) {
    const Scene scene = floor_and_sphere(1.0f);
    const Accelerator accel(scene, 1);
    const Camera camera = make_camera({0.0f, 3.0f, 9.0f}, {0.0f, 0.8f, 0.0f}, 40.0f);
    const uint32_t w = 24, h = 18;
    RenderStats stats;
    const Image image = Renderer(accel, make_settings(w, h), camera).render(1, 8, nullptr, stats);
    EXPECT_EQ(stats.samples, uint64_t(w) * h);
    const WhittedIntegrator integrator(accel, make_settings(w, h));
    const ViewCamera pinhole(camera, w, h);
    for (uint32_t y = 0; y < h; ++y) {
        for (uint32_t x = 0; x < w; ++x) {
            RayCounts rays;
            const Ray centre = pinhole.generate_ray(float(x) + 0.5f, float(y) + 0.5f);
            ASSERT_EQ(image.pixel(x, y), integrator.radiance(centre, PixelSampler(0, 0), rays)) << x << ", " << y;
        }
    }
    for (PixelFilter filter : {BOX, TENT, GAUSSIAN, GRID}) {
        RenderSettings settings = make_settings(w, h);
        settings.set_pixel_filter(filter);
        settings.set_samples_per_pixel(1);
        EXPECT_EQ(Renderer(accel, settings, camera).render(1, 8, nullptr, stats).rgb, image.rgb)
            << PixelFilter_Name(filter);
    }
}

TEST(AntiAliasing, GridRefusesWhatItCannotDo) {
    const Scene scene = floor_and_sphere(1.0f);
    const Accelerator accel(scene, 1);
    const Camera camera = make_camera({0.0f, 3.0f, 9.0f}, vec3(0.0f));
    RenderSettings settings = make_settings(8, 8);
    settings.set_pixel_filter(GRID);
    settings.set_samples_per_pixel(10);
    try {
        Renderer(accel, settings, camera);
        FAIL() << "10 samples on a grid accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("settings.samples_per_pixel"), std::string::npos) << e.what();
    }
    settings.set_samples_per_pixel(16);
    settings.set_adaptive_threshold(0.05f);
    try {
        Renderer(accel, settings, camera);
        FAIL() << "adaptive GRID accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("settings.adaptive_threshold"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace rt
