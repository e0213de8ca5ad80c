#include <cmath>

#include <gtest/gtest.h>

#include "geometry/accel.h"
#include "integrator/render.h"
#include "integrator/default_camera.h"
#include "test_meshes.h"
#include "test_scenes.h"

namespace rt {
namespace {

using namespace rt::testing;

Image render_image(const Scene& scene, const Camera& camera, uint32_t w, uint32_t h, unsigned threads,
                   uint32_t tile) {
    const Accelerator accel(scene, threads);
    const Renderer renderer(accel, make_settings(w, h), camera);
    RenderStats counts;
    return renderer.render(threads, tile, nullptr, counts);
}

// Acne test: the same lit floor and sphere at scales 1e-4, 1 and 1e5 gives the
// same image, and no floor pixel that sees the light is darkened by its own
// surface.
TEST(Render, NoSelfShadowingAtAnyScale) {
    const uint32_t w = 96, h = 72;
    std::vector<Image> images;
    for (float scale : {1e-4f, 1.0f, 1e5f}) {
        const Scene scene = floor_and_sphere(scale);
        const Camera camera = make_camera(vec3(0.0f, 3.0f, 9.0f) * scale, vec3(0.0f, 0.8f, 0.0f) * scale, 40.0f);
        images.push_back(render_image(scene, camera, w, h, 0, 16));

        // Every floor pixel outside the sphere's shadow must receive light: a
        // fixed epsilon makes some of them shadow themselves at small scales.
        const Accelerator accel(scene, 1);
        const ViewCamera pinhole(camera, w, h);
        int self_shadowed = 0, lit = 0;
        for (uint32_t y = 0; y < h; ++y) {
            for (uint32_t x = 0; x < w; ++x) {
                const Ray ray = pinhole.generate_ray(float(x) + 0.5f, float(y) + 0.5f);
                Hit hit;
                if (!accel.intersect(ray, hit) || hit.primitive >= scene.triangles.size()) continue;
                // Exact shadow test in double precision against the sphere alone.
                const dvec3 p = dvec3(ray.origin) + double(hit.t) * dvec3(ray.direction);
                const dvec3 l = dvec3(scene.lights[0].position) - p;
                const dvec3 f = p - dvec3(scene.spheres[0].center);
                const dvec3 d = glm::normalize(l);
                const double b = glm::dot(f, d);
                const double disc = b * b - (glm::dot(f, f) - double(scene.spheres[0].radius) * scene.spheres[0].radius);
                const bool shadowed = disc > 0.0 && -b - std::sqrt(disc) > 0.0;
                if (shadowed) continue;
                ++lit;
                if (images.back().pixel(x, y).r <= 0.0f) ++self_shadowed;
            }
        }
        EXPECT_GT(lit, int(w * h / 4)) << "scale " << scale;
        EXPECT_EQ(self_shadowed, 0) << "scale " << scale;
    }
    // Up to scale the images agree; single pixels on the shadow's and the
    // sphere's outlines may flip where the hit point lands within rounding.
    for (size_t k : {0u, 2u}) {
        int differing = 0;
        for (size_t i = 0; i < images[1].rgb.size(); ++i)
            differing += std::abs(images[k].rgb[i] - images[1].rgb[i]) > 1e-3f * (1.0f + images[1].rgb[i]);
        EXPECT_LE(differing, int(images[1].rgb.size() / 500)) << "scale index " << k;
    }
}

TEST(Render, SameImageForAnyTilingAndThreadCount) {
    const Scene scene = floor_and_sphere(1.0f);
    const Camera camera = make_camera({0.0f, 3.0f, 9.0f}, {0.0f, 0.8f, 0.0f}, 40.0f);
    const Image reference = render_image(scene, camera, 67, 43, 1, 1000);
    for (auto [threads, tile] : {std::pair{1u, 7u}, std::pair{2u, 16u}, std::pair{4u, 1u}, std::pair{3u, 64u}}) {
        const Image image = render_image(scene, camera, 67, 43, threads, tile);
        EXPECT_EQ(image.rgb, reference.rgb) << threads << " threads, tile " << tile;
    }
}

// Several samples per pixel, adaptive stopping, a filter reaching into the
// neighbours and a spherical light: still a function of the pixel alone.
TEST(Render, SameImageForAnyTilingAndThreadCountWithManySamples) {
    Scene scene = floor_and_sphere(1.0f);
    scene.lights[0].radius = 0.5f;
    const Camera camera = make_camera({0.0f, 3.0f, 9.0f}, {0.0f, 0.8f, 0.0f}, 40.0f);
    const Accelerator accel(scene, 1);
    for (float threshold : {0.0f, 0.5f}) {
        RenderSettings settings = make_settings(37, 23);
        settings.set_samples_per_pixel(48);
        settings.set_adaptive_threshold(threshold);
        settings.set_light_samples(3);
        const Renderer renderer(accel, settings, camera);
        RenderStats reference_stats;
        const Image reference = renderer.render(1, 1000, nullptr, reference_stats);
        for (auto [threads, tile] : {std::pair{2u, 5u}, std::pair{4u, 1u}, std::pair{3u, 16u}}) {
            RenderStats stats;
            EXPECT_EQ(renderer.render(threads, tile, nullptr, stats).rgb, reference.rgb)
                << "threshold " << threshold << ", " << threads << " threads, tile " << tile;
            EXPECT_EQ(stats.samples, reference_stats.samples);
            EXPECT_EQ(stats.rays.total(), reference_stats.rays.total());
        }
        if (threshold == 0.0f) EXPECT_EQ(reference_stats.samples, uint64_t(48) * 37 * 23);
        else EXPECT_LT(reference_stats.samples, uint64_t(48) * 37 * 23);
    }
}

// The colour alone of a still mesh goes through camera packets
// (render_packet); asking for an auxiliary layer takes each pixel's rays one
// by one (render_pixel). Both give the same colours, bit for bit, and count
// the same samples and rays, with one sample, many, and adaptive stopping,
// for tiles that cut the 4 x 4 packets anywhere.
TEST(Render, CameraPacketsGiveTheImageOfSingleRays) {
    const Scene scene = sample_scene("dragon_4.glb");
    const Accelerator accel(scene, 2);
    ASSERT_TRUE(accel.packets_serve());
    for (auto [samples, threshold] : {std::pair{1u, 0.0f}, std::pair{8u, 0.0f}, std::pair{32u, 0.3f}}) {
        RenderSettings settings = make_settings(61, 45);
        settings.set_samples_per_pixel(samples);
        settings.set_adaptive_threshold(threshold);
        const Renderer renderer(accel, settings, default_camera(scene));
        RenderStats single_stats;
        AuxImage aux(61, 45, {DEPTH});
        const Image single = renderer.render(2, 16, nullptr, single_stats, &aux);
        for (uint32_t tile : {16u, 7u, 1000u}) {
            RenderStats stats;
            EXPECT_EQ(renderer.render(2, tile, nullptr, stats).rgb, single.rgb) << samples << " spp, tile " << tile;
            EXPECT_EQ(stats.samples, single_stats.samples);
            EXPECT_EQ(stats.rays.total(), single_stats.rays.total());
        }
    }
}

// A moving scene's camera rays go as packets too, each at its sample's time.
TEST(Render, MovingCameraPacketsGiveTheImageOfSingleRays) {
    Scene scene = sample_scene("dragon_4.glb");
    const float shift = 0.05f * scene.bounds().extent().x;
    for (const vec3& p : scene.positions) scene.positions_close.push_back(p + vec3(shift, 0.0f, 0.0f));
    scene.normals_close = scene.normals;
    const Accelerator accel(scene, 2);
    ASSERT_TRUE(accel.packets_serve());
    // 36 samples with adaptive sampling: packets of rays sorted by time from
    // groups of 8 samples, then 4, while pixels stop after 32 (the rule's
    // minimum at this threshold) or go on.
    for (uint32_t samples : {1u, 6u, 36u}) {
        RenderSettings settings = make_settings(61, 45);
        settings.set_samples_per_pixel(samples);
        if (samples == 36) settings.set_adaptive_threshold(0.5f);
        const Renderer renderer(accel, settings, default_camera(scene));
        RenderStats single_stats, stats;
        AuxImage aux(61, 45, {DEPTH});
        const Image single = renderer.render(2, 16, nullptr, single_stats, &aux);
        EXPECT_EQ(renderer.render(2, 16, nullptr, stats).rgb, single.rgb) << samples << " spp";
        EXPECT_EQ(stats.rays.total(), single_stats.rays.total());
        EXPECT_EQ(stats.samples, single_stats.samples);
        if (samples == 36) {
            EXPECT_LT(stats.samples, 61u * 45u * 36u) << "some pixels stop early";
            EXPECT_GT(stats.samples, 61u * 45u * 32u) << "some pixels do not";
        }
    }
}

// A spherical light's and a soft sun's samples at a hit go as packets from
// one point; the auxiliary outputs' render, which traces ray by ray, agrees.
TEST(Render, LightSamplePacketsGiveTheImageOfSingleRays) {
    Scene scene = sample_scene("dragon_4.glb");
    const Bounds3 box = scene.bounds();
    Light sphere;
    sphere.position = vec3(box.center().x, box.max.y + box.extent().y, box.max.z);
    sphere.radius = 0.03f * box.extent().x;
    sphere.intensity = vec3(20.0f);
    scene.lights = {sphere};
    const Accelerator accel(scene, 2);
    ASSERT_TRUE(accel.packets_serve());
    RenderSettings settings = make_settings(48, 36);
    settings.set_samples_per_pixel(2);
    settings.set_light_samples(24);  // a packet and a half
    const Renderer renderer(accel, settings, default_camera(scene));
    RenderStats single_stats, stats;
    AuxImage aux(48, 36, {DEPTH});
    const Image single = renderer.render(2, 16, nullptr, single_stats, &aux);
    EXPECT_EQ(renderer.render(2, 16, nullptr, stats).rgb, single.rgb);
    EXPECT_EQ(stats.rays.shadow, single_stats.rays.shadow);
    EXPECT_GT(stats.rays.shadow, 48u * 36u * 2u * 12u) << "most pixels see the dragon or the ground lit";
}

// The debugger traces every sample of the pixel and agrees with the render.
TEST(Render, DebugPixelTracesEverySample) {
    Scene scene = floor_and_sphere(1.0f);
    scene.lights[0].radius = 0.5f;
    const Accelerator accel(scene, 1);
    RenderSettings settings = make_settings(16, 12);
    settings.set_samples_per_pixel(5);
    settings.set_light_samples(2);
    const Renderer renderer(accel, settings, make_camera({0.0f, 3.0f, 9.0f}, {0.0f, 0.8f, 0.0f}, 40.0f));
    const DebugPath path = renderer.debug_pixel(8, 8);
    int primaries = 0;
    for (const RaySegment& segment : path.segments()) primaries += segment.kind() == PRIMARY;
    EXPECT_EQ(primaries, 5);
    float rgb[3];
    renderer.render_tile({8, 8, 1, 1}, rgb);
    ASSERT_EQ(path.color_size(), 3);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(path.color(c), rgb[c]);
}

TEST(Render, TileOutsideTheImageIsRefused) {
    const Scene scene = floor_and_sphere(1.0f);
    const Accelerator accel(scene, 1);
    const Renderer renderer(accel, make_settings(16, 16), make_camera({0.0f, 3.0f, 9.0f}, vec3(0.0f)));
    float rgb[3 * 16 * 16];
    EXPECT_THROW(renderer.render_tile({8, 8, 9, 1}, rgb), std::invalid_argument);
    EXPECT_THROW(renderer.render_tile({0, 0, 0, 1}, rgb), std::invalid_argument);
    EXPECT_THROW(renderer.debug_pixel(16, 0), std::invalid_argument);
}

TEST(Render, InvalidSettingsAndCamerasAreRefused) {
    const Scene scene = floor_and_sphere(1.0f);
    const Accelerator accel(scene, 1);
    EXPECT_THROW(Renderer(accel, make_settings(0, 16), make_camera({0.0f, 3.0f, 9.0f}, vec3(0.0f))),
                 std::invalid_argument);
    EXPECT_THROW(Renderer(accel, make_settings(8, 8), make_camera(vec3(1.0f), vec3(1.0f))), std::invalid_argument);
    EXPECT_THROW(Renderer(accel, make_settings(8, 8), make_camera({0.0f, 3.0f, 0.0f}, vec3(0.0f))),
                 std::invalid_argument);  // up parallel to the view direction
}

}  // namespace
}  // namespace rt
