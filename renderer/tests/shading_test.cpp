#include <gtest/gtest.h>

#include "geometry/accel.h"
#include "integrator/render.h"
#include "test_scenes.h"

namespace rt {
namespace {

using namespace rt::testing;

// Diffuse plane under a point light, seen from above: every pixel equals
// Kd/pi * I cos(theta) / d^2 at its hit point.
TEST(Shading, LambertianPlaneMatchesTheClosedForm) {
    Scene scene;
    const vec3 kd(0.5f, 0.25f, 0.75f);
    add_quad(scene, {-10.0f, 0.0f, 10.0f}, {20.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -20.0f}, add_material(scene, kd));
    const vec3 light(0.5f, 2.0f, -0.3f);
    add_point_light(scene, light, 4.0f);
    const Accelerator accel(scene, 1);
    const Camera camera = make_camera({0.0f, 5.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, 60.0f, {0.0f, 0.0f, -1.0f});
    const Renderer renderer(accel, make_settings(32, 32), camera);
    const ViewCamera pinhole(camera, 32, 32);
    for (uint32_t y = 0; y < 32; y += 5) {
        for (uint32_t x = 0; x < 32; x += 5) {
            const Ray ray = pinhole.generate_ray(float(x) + 0.5f, float(y) + 0.5f);
            const vec3 p = ray.at(-ray.origin.y / ray.direction.y);
            const vec3 to_light = light - p;
            const float d2 = glm::dot(to_light, to_light);
            const vec3 expected = kd / kPi * 4.0f * (to_light.y / std::sqrt(d2)) / d2;
            const vec3 got = render_pixel(renderer, x, y);
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], expected[c], 1e-5f * expected[c] + 1e-7f);
        }
    }
}

// Sphere lit and seen head-on: the normalized Phong lobe peaks at
// (Kd/pi + Ks (n+2) / (2 pi)) I / d^2.
TEST(Shading, PhongSphereHighlightMatchesTheClosedForm) {
    Scene scene;
    const vec3 kd(0.4f), ks(0.5f);
    const float n = 10.0f;
    scene.spheres.push_back({vec3(0.0f), 1.0f, add_material(scene, kd, ks, n)});
    add_point_light(scene, {0.0f, 0.0f, 5.0f}, 16.0f);
    const Accelerator accel(scene, 1);
    const Renderer renderer(accel, make_settings(33, 33), make_camera({0.0f, 0.0f, 10.0f}, vec3(0.0f), 20.0f));
    const vec3 got = render_pixel(renderer, 16, 16);
    const vec3 expected = (kd / kPi + ks * (n + 2.0f) / (2.0f * kPi)) * 16.0f / 16.0f;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], expected[c], 2e-3f * expected[c]);
    // Away from the highlight the specular term falls off.
    EXPECT_LT(render_pixel(renderer, 16, 9).r, got.r);
}

TEST(Shading, FacesAwayFromTheLightAreBlack) {
    Scene scene;
    scene.spheres.push_back({vec3(0.0f), 1.0f, add_material(scene, vec3(0.8f))});
    add_point_light(scene, {0.0f, 0.0f, -5.0f}, 16.0f);  // behind the sphere
    const Accelerator accel(scene, 1);
    const Renderer renderer(accel, make_settings(9, 9), make_camera({0.0f, 0.0f, 10.0f}, vec3(0.0f), 10.0f));
    EXPECT_EQ(render_pixel(renderer, 4, 4), vec3(0.0f));
}

TEST(Shading, ShadowsBlockTheLight) {
    Scene scene;
    add_quad(scene, {-10.0f, 0.0f, 10.0f}, {20.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -20.0f}, add_material(scene, vec3(0.5f)));
    scene.spheres.push_back({vec3(0.0f, 1.0f, 0.0f), 0.5f, add_material(scene, vec3(0.5f))});
    add_point_light(scene, {0.0f, 3.0f, 0.0f}, 9.0f);
    const Accelerator accel(scene, 1);
    // Look at the floor from the side, under the sphere's shadow.
    const Renderer renderer(accel, make_settings(41, 41),
                            make_camera({0.0f, 0.5f, 6.0f}, {0.0f, 0.0f, 0.0f}, 5.0f));
    EXPECT_EQ(render_pixel(renderer, 20, 20), vec3(0.0f));  // floor point (0, 0, 0) is in shadow
    DebugPath path = renderer.debug_pixel(20, 20);
    ASSERT_GE(path.segments_size(), 2);
    EXPECT_EQ(path.segments(1).kind(), SHADOW);
    EXPECT_EQ(path.segments(1).outcome(), OCCLUDED);
}

// Two facing mirrors: the reflection chain stops at max_depth exactly.
TEST(Shading, MirrorCorridorStopsAtMaxDepth) {
    Scene scene;
    const uint32_t mirror = add_material(scene, vec3(0.1f), vec3(0.0f), 1.0f, vec3(1.0f));
    add_quad(scene, {-1.0f, -5.0f, -5.0f}, {0.0f, 10.0f, 0.0f}, {0.0f, 0.0f, 10.0f}, mirror);  // x = -1, faces +x
    add_quad(scene, {1.0f, -5.0f, -5.0f}, {0.0f, 0.0f, 10.0f}, {0.0f, 10.0f, 0.0f}, mirror);   // x = +1, faces -x
    add_point_light(scene, {0.0f, 0.0f, 0.0f}, 1.0f);
    const Accelerator accel(scene, 1);
    for (uint32_t depth : {0u, 1u, 7u, 64u}) {
        RenderSettings settings = make_settings(3, 3);
        settings.set_max_depth(depth);
        settings.set_min_contribution(0.0f);
        const Renderer renderer(accel, settings, make_camera({0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.01f}));
        const DebugPath path = renderer.debug_pixel(1, 1);
        int reflections = 0;
        for (const auto& s : path.segments()) reflections += s.kind() == REFLECTION;
        EXPECT_EQ(reflections, int(depth));
    }
}

// The cutoff works on the path weight: with reflectance 0.5 and a threshold of
// 0.1 the weights 0.5, 0.25, 0.125 pass and 0.0625 does not.
TEST(Shading, SignificanceCutoffUsesThePathWeight) {
    Scene scene;
    const uint32_t mirror = add_material(scene, vec3(0.1f), vec3(0.0f), 1.0f, vec3(0.5f));
    add_quad(scene, {-1.0f, -5.0f, -5.0f}, {0.0f, 10.0f, 0.0f}, {0.0f, 0.0f, 10.0f}, mirror);
    add_quad(scene, {1.0f, -5.0f, -5.0f}, {0.0f, 0.0f, 10.0f}, {0.0f, 10.0f, 0.0f}, mirror);
    const Accelerator accel(scene, 1);
    RenderSettings settings = make_settings(3, 3);
    settings.set_max_depth(20);
    settings.set_min_contribution(0.1f);
    const Renderer renderer(accel, settings, make_camera({0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.01f}));
    const DebugPath path = renderer.debug_pixel(1, 1);
    int reflections = 0;
    for (const auto& s : path.segments()) reflections += s.kind() == REFLECTION;
    EXPECT_EQ(reflections, 3);
}

TEST(Shading, MissesShowTheBackground) {
    Scene scene;
    scene.background = vec3(0.1f, 0.2f, 0.3f);
    const Accelerator accel(scene, 1);
    const Renderer renderer(accel, make_settings(4, 4), make_camera({0.0f, 0.0f, 1.0f}, vec3(0.0f)));
    EXPECT_EQ(render_pixel(renderer, 2, 2), scene.background);
}

}  // namespace
}  // namespace rt
