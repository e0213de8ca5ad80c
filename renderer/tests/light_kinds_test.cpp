// Spot, ranged and directional lights, and the default rig of a scene without
// lights, against the formulas of glTF's KHR_lights_punctual.
#include <cmath>

#include <gtest/gtest.h>

#include "geometry/accel.h"
#include "integrator/camera.h"
#include "integrator/default_camera.h"
#include "integrator/render.h"
#include "loader_test_util.h"
#include "test_scenes.h"

namespace rt {
namespace {

using namespace rt::testing;

void expect_vec3(vec3 actual, vec3 expected) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(actual[c], expected[c], 1e-5f) << "component " << c;
}

// The specification's formulas, written out apart from the renderer's.
float expected_spot(float cos_angle, float inner, float outer) {
    const float t = std::clamp((cos_angle - std::cos(outer)) / (std::cos(inner) - std::cos(outer)), 0.0f, 1.0f);
    return t * t;
}
float expected_window(float d, float range) {
    if (range == 0.0f) return 1.0f;
    const float w = std::clamp(1.0f - std::pow(d / range, 4.0f), 0.0f, 1.0f);
    return w * w;
}

// A grey floor under a light 2 above the origin, seen from straight above.
// Every pixel against Kd/pi * I cos / d^2 times the cone and the window; counts
// the pixels inside the inner cone, between the cones and outside.
void check_floor(const Light& light, float inner, float outer, int (&regimes)[3]) {
    Scene scene;
    const vec3 kd(0.5f);
    add_quad(scene, {-10.0f, 0.0f, 10.0f}, {20.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -20.0f}, add_material(scene, kd));
    scene.lights.push_back(light);
    const Accelerator accel(scene, 1);
    const Camera camera = make_camera({0.0f, 6.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, 90.0f, {0.0f, 0.0f, -1.0f});
    const Renderer renderer(accel, make_settings(41, 41), camera);
    const ViewCamera pinhole(camera, 41, 41);
    for (uint32_t y = 0; y < 41; y += 2) {
        for (uint32_t x = 0; x < 41; x += 2) {
            const Ray ray = pinhole.generate_ray(float(x) + 0.5f, float(y) + 0.5f);
            const vec3 p = ray.at(-ray.origin.y / ray.direction.y);
            const vec3 to_light = light.position - p;
            const float d = glm::length(to_light);
            const float cos_angle = to_light.y / d;  // from the axis (straight down), and at the floor
            float expected = kd.x / kPi * light.intensity.x * cos_angle / (d * d) * expected_window(d, light.range);
            if (light.kind == SPOT) {
                const float falloff = expected_spot(cos_angle, inner, outer);
                expected *= falloff;
                ++regimes[falloff == 1.0f ? 0 : falloff > 0.0f ? 1 : 2];
            }
            EXPECT_NEAR(render_pixel(renderer, x, y).x, expected, 1e-4f * expected + 1e-7f) << x << ", " << y;
        }
    }
}

TEST(LightKinds, SpotFallsOffSmoothlyBetweenItsCones) {
    Light spot;
    spot.kind = SPOT;
    spot.position = {0.0f, 2.0f, 0.0f};
    spot.intensity = vec3(20.0f);
    spot.direction = {0.0f, -1.0f, 0.0f};
    const float inner = 0.4f, outer = 0.9f;
    spot.cos_inner = std::cos(inner);
    spot.cos_outer = std::cos(outer);
    int regimes[3] = {0, 0, 0};
    check_floor(spot, inner, outer, regimes);
    EXPECT_GT(regimes[0], 0);  // the test saw every part of the cone
    EXPECT_GT(regimes[1], 0);
    EXPECT_GT(regimes[2], 0);
}

TEST(LightKinds, RangeWindowsPointAndSpotLights) {
    Light point;
    point.position = {0.0f, 2.0f, 0.0f};
    point.intensity = vec3(20.0f);
    point.range = 4.0f;  // reaches the floor out to sqrt(12) from the centre; the view spans 6
    EXPECT_FALSE(point.plain_point());
    int regimes[3] = {0, 0, 0};
    check_floor(point, 0.0f, 0.0f, regimes);
    // Beyond the range, nothing.
    Scene scene;
    add_quad(scene, {-10.0f, 0.0f, 10.0f}, {20.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -20.0f}, add_material(scene, vec3(0.5f)));
    scene.lights.push_back(point);
    const Accelerator accel(scene, 1);
    const Camera camera = make_camera({0.0f, 6.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, 90.0f, {0.0f, 0.0f, -1.0f});
    const Renderer renderer(accel, make_settings(41, 41), camera);
    EXPECT_GT(render_pixel(renderer, 20, 20).x, 0.0f);
    EXPECT_EQ(render_pixel(renderer, 0, 20).x, 0.0f);
}

// Floor y = 0 under a roof at y = 1 that covers x < 0; the camera between them
// looks down at the floor through x in [-0.5, 0.5]; the sun is straight up.
// One row of the image, left to right.
std::vector<float> shadow_row(float angular_diameter_degrees) {
    Scene scene;
    const uint32_t grey = add_material(scene, vec3(0.5f));
    add_quad(scene, {-10.0f, 0.0f, 10.0f}, {20.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -20.0f}, grey);
    add_quad(scene, {-10.0f, 1.0f, 10.0f}, {10.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -20.0f}, grey);
    Light sun;
    sun.kind = DIRECTIONAL;
    sun.direction = {0.0f, -1.0f, 0.0f};
    sun.intensity = vec3(3.0f);
    sun.angular_diameter = angular_diameter_degrees * kPi / 180.0f;
    scene.lights.push_back(sun);
    const Accelerator accel(scene, 1);
    RenderSettings settings = make_settings(64, 8);
    settings.set_light_samples(256);
    // A 90 degree horizontal view: fov_y from the aspect 8.
    const float fov_y = 2.0f * std::atan(std::tan(0.25f * kPi) / 8.0f) * 180.0f / kPi;
    const Camera camera = make_camera({0.0f, 0.5f, 0.0f}, {0.0f, 0.0f, 0.0f}, fov_y, {0.0f, 0.0f, -1.0f});
    const Renderer wide(accel, settings, camera);
    std::vector<float> row;
    for (uint32_t x = 0; x < 64; ++x) row.push_back(render_pixel(wide, x, 4).x);
    return row;
}

// Pixels neither in full shadow nor fully lit.
int penumbra_pixels(const std::vector<float>& row, float full) {
    int n = 0;
    for (float v : row) n += v > 0.02f * full && v < 0.98f * full;
    return n;
}

TEST(LightKinds, DirectionalLightCastsAHardShadowToInfinity) {
    const std::vector<float> row = shadow_row(0.0f);
    const float full = 0.5f / kPi * 3.0f;
    // Camera x grows to the image's right: the roof's shadow is on the left.
    EXPECT_EQ(row.front(), 0.0f);
    EXPECT_NEAR(row.back(), full, 1e-5f);
    EXPECT_EQ(penumbra_pixels(row, full), 0);
}

TEST(LightKinds, AngularDiameterWidensThePenumbra) {
    const float full = 0.5f / kPi * 3.0f;
    const std::vector<float> small = shadow_row(5.0f), large = shadow_row(20.0f);
    const int narrow = penumbra_pixels(small, full), wide = penumbra_pixels(large, full);
    // Width on the floor 2 tan(diameter / 2) at height 1, over 64 pixels for 1:
    // about 5.6 and 22.6 pixels.
    EXPECT_GE(narrow, 3);
    EXPECT_LE(narrow, 8);
    EXPECT_GE(wide, 18);
    EXPECT_LE(wide, 26);
    // Half the sun is seen above the roof's edge; far from it, all (cos ~ 1).
    EXPECT_NEAR(large[31] + large[32], full, 0.1f * full);
    EXPECT_NEAR(large.back(), full, 0.02f * full);
}

GltfDoc unlit_triangle() {
    GltfDoc doc;
    doc.add_mesh_node({{"attributes", {{"POSITION", doc.add_vec3({0, 0, 0, 1, 0, 0, 0, 1, 0})}}}});
    return doc;
}

float brightest(const Scene& scene, RenderSettings settings, vec3& corner) {
    const Accelerator accel(scene, 1);
    const Renderer renderer(accel, settings, default_camera(scene));
    float best = 0.0f;
    for (uint32_t y = 0; y < settings.height(); ++y)
        for (uint32_t x = 0; x < settings.width(); ++x) best = std::max(best, render_pixel(renderer, x, y).x);
    corner = render_pixel(renderer, 0, 0);
    return best;
}

TEST(LightKinds, ASceneWithoutLightsGetsTheDefaultRig) {
    const Scene scene = load_bytes(unlit_triangle().glb(), "unlit.glb");
    ASSERT_EQ(scene.rig_lights, 2u);
    ASSERT_EQ(scene.lights.size(), 2u);
    EXPECT_EQ(scene.lights[0].kind, DIRECTIONAL);
    EXPECT_TRUE(has_warning(scene, "scene has no lights: lit by the default light rig"));
    RenderSettings settings = make_settings(16, 16);
    vec3 corner;
    EXPECT_GT(brightest(scene, settings, corner), 0.1f);
    ASSERT_TRUE(scene.rig_background.solid());
    expect_vec3(corner, scene.rig_background.top);  // the sky where rays miss
    EXPECT_GT(scene.rig_background.top.x, 0.0f);
    settings.set_light_rig(NO_RIG);
    EXPECT_EQ(brightest(scene, settings, corner), 0.0f);  // black: no light, a black background
    EXPECT_TRUE(scene.background.black());
    expect_vec3(corner, vec3(0.0f));
}

}  // namespace
}  // namespace rt
