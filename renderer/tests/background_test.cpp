// The background (geometry/background.h): what camera, reflection and
// refraction rays see when they miss, from the scene or the settings.
#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

#include "geometry/accel.h"
#include "integrator/render.h"
#include "test_scenes.h"

namespace rt {
namespace {

using namespace rt::testing;

const vec3 kBottom(0.1f, 0.2f, 0.3f), kHorizon(0.9f, 0.6f, 0.3f), kTop(0.2f, 0.4f, 2.0f);

void expect_near(vec3 actual, vec3 expected, float tolerance = 1e-6f) {
    EXPECT_NEAR(actual.x, expected.x, tolerance);
    EXPECT_NEAR(actual.y, expected.y, tolerance);
    EXPECT_NEAR(actual.z, expected.z, tolerance);
}

void set_color(google::protobuf::RepeatedField<float>* field, vec3 c) {
    field->Clear();
    for (int i = 0; i < 3; ++i) field->Add(c[i]);
}

// One pixel, the centre of a 3x3 image, so its ray is the camera's axis.
vec3 centre_pixel(const Scene& scene, const RenderSettings& settings, vec3 from, vec3 towards,
                  vec3 up = vec3(0.0f, 1.0f, 0.0f)) {
    const Accelerator accel(scene, 1);
    const Renderer renderer(accel, settings, make_camera(from, from + towards, 10.0f, up));
    return render_pixel(renderer, 1, 1);
}

TEST(Background, GradientFollowsTheDirectionsHeight) {
    const Background sky(kBottom, kHorizon, kTop);
    expect_near(sky({0.0f, -1.0f, 0.0f}), kBottom);
    expect_near(sky({1.0f, 0.0f, 0.0f}), kHorizon);
    expect_near(sky({0.0f, 1.0f, 0.0f}), kTop);
    const vec3 up30 = glm::normalize(vec3(std::sqrt(3.0f), 1.0f, 0.0f));  // 30 degrees up: y = 0.5
    expect_near(sky(up30), 0.5f * (kHorizon + kTop));
    expect_near(sky(vec3(up30.x, -up30.y, up30.z)), 0.5f * (kHorizon + kBottom));
    EXPECT_FALSE(sky.solid());

    const Background ramp = Background::ramp(kBottom, kTop);
    expect_near(ramp({0.0f, 0.0f, -1.0f}), 0.5f * (kBottom + kTop));
    expect_near(ramp(up30), 0.25f * kBottom + 0.75f * kTop);
    const Background solid(kHorizon);
    EXPECT_TRUE(solid.solid());
    expect_near(solid(up30), kHorizon);
}

TEST(Background, CameraRaysThatMissSeeTheGradient) {
    Scene scene;
    scene.background = Background(kBottom, kHorizon, kTop);
    const RenderSettings settings = make_settings(3, 3);
    expect_near(centre_pixel(scene, settings, vec3(0.0f), {0.0f, 1.0f, 0.0f}, {0.0f, 0.0f, -1.0f}), kTop);
    expect_near(centre_pixel(scene, settings, vec3(0.0f), {0.0f, -1.0f, 0.0f}, {0.0f, 0.0f, -1.0f}), kBottom);
    expect_near(centre_pixel(scene, settings, vec3(0.0f), {1.0f, 0.0f, 0.0f}), kHorizon);
    expect_near(centre_pixel(scene, settings, vec3(0.0f), {std::sqrt(3.0f), 1.0f, 0.0f}), 0.5f * (kHorizon + kTop),
                1e-5f);
}

TEST(Background, SettingsOverrideTheScenes) {
    Scene scene;
    scene.background = vec3(1.0f, 0.0f, 0.0f);
    RenderSettings settings = make_settings(3, 3);
    set_color(settings.mutable_background(), {0.0f, 0.5f, 0.0f});
    expect_near(centre_pixel(scene, settings, vec3(0.0f), {0.0f, 0.0f, -1.0f}), {0.0f, 0.5f, 0.0f});

    settings.clear_background();
    BackgroundGradient& gradient = *settings.mutable_background_gradient();
    set_color(gradient.mutable_bottom(), kBottom);
    set_color(gradient.mutable_top(), kTop);
    // Without a horizon, the mean of bottom and top.
    expect_near(centre_pixel(scene, settings, vec3(0.0f), {0.0f, 0.0f, -1.0f}), 0.5f * (kBottom + kTop));
    set_color(gradient.mutable_horizon(), kHorizon);
    expect_near(centre_pixel(scene, settings, vec3(0.0f), {0.0f, 0.0f, -1.0f}), kHorizon);
}

std::string settings_error(const RenderSettings& settings) {
    const Scene scene;
    const Accelerator accel(scene, 1);
    try {
        const Renderer renderer(accel, settings, make_camera(vec3(0.0f), {0.0f, 0.0f, -1.0f}));
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "no error";
}

TEST(Background, BadSettingsNameTheField) {
    RenderSettings settings = make_settings(3, 3);
    set_color(settings.mutable_background(), {0.1f, -0.5f, 0.0f});
    EXPECT_EQ(settings_error(settings), "settings.background[1]: -0.5 is below the minimum 0");
    set_color(settings.mutable_background(), {0.1f, NAN, 0.0f});
    EXPECT_EQ(settings_error(settings), "settings.background[1]: must be a finite number");
    set_color(settings.mutable_background(), {2e6f, 0.0f, 0.0f});
    EXPECT_EQ(settings_error(settings), "settings.background[0]: 2e+06 is above the maximum 1e+06");
    settings.mutable_background()->RemoveLast();
    EXPECT_EQ(settings_error(settings), "settings.background: needs 3 values, got 2");

    set_color(settings.mutable_background(), vec3(0.5f));
    set_color(settings.mutable_background_gradient()->mutable_bottom(), kBottom);
    set_color(settings.mutable_background_gradient()->mutable_top(), kTop);
    EXPECT_EQ(settings_error(settings),
              "settings.background_gradient: give background or background_gradient, not both");
    settings.clear_background();
    settings.mutable_background_gradient()->clear_top();
    EXPECT_EQ(settings_error(settings), "settings.background_gradient.top: is required");
}

// A mirror tilted 45 degrees sends the camera's level ray straight up: the
// pixel is the mirror's reflectance times the top of the sky.
TEST(Background, AMirrorReflectsTheBackground) {
    Scene scene;
    scene.background = Background(kBottom, kHorizon, kTop);
    const vec3 reflectance(0.5f, 0.25f, 1.0f);
    const uint32_t mirror = add_material(scene, vec3(0.0f), vec3(0.0f), 1.0f, reflectance);
    // A square in the plane y + z = 0 (normal (0, 1, 1) / sqrt 2), facing the camera on +z.
    add_quad(scene, {-1.0f, -1.0f, 1.0f}, {2.0f, 0.0f, 0.0f}, {0.0f, 2.0f, -2.0f}, mirror);
    const vec3 pixel = centre_pixel(scene, make_settings(3, 3), {0.0f, 0.0f, 5.0f}, {0.0f, 0.0f, -1.0f});
    expect_near(pixel, reflectance * kTop, 1e-5f);
}

// Glass of index 1 bends nothing and reflects nothing: the refracted ray
// sees what the camera ray would have.
TEST(Background, RefractionRaysSeeTheBackground) {
    Scene scene;
    scene.background = Background(kBottom, kHorizon, kTop);
    const uint32_t glass = add_material(scene, vec3(0.0f));
    scene.materials[glass].transmission = vec3(1.0f);
    scene.materials[glass].ior = 1.0f;
    add_quad(scene, {-1.0f, -1.0f, 0.0f}, {2.0f, 0.0f, 0.0f}, {0.0f, 2.0f, 0.0f}, glass);
    const vec3 pixel = centre_pixel(scene, make_settings(3, 3), {0.0f, 0.0f, 5.0f}, {0.0f, 0.0f, -1.0f});
    expect_near(pixel, kHorizon, 1e-5f);
}

// A lit floor does not change under a bright sky: shadow rays never see it.
TEST(Background, ShadowRaysDoNotSeeIt) {
    Scene scene;
    add_quad(scene, {-10.0f, 0.0f, 10.0f}, {20.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -20.0f},
             add_material(scene, vec3(0.5f)));
    add_point_light(scene, {0.5f, 2.0f, -0.3f}, 4.0f);
    RenderSettings settings = make_settings(3, 3);
    const vec3 dark = centre_pixel(scene, settings, {0.0f, 5.0f, 0.0f}, {0.0f, -1.0f, 0.0f}, {0.0f, 0.0f, -1.0f});
    set_color(settings.mutable_background(), vec3(100.0f));
    const vec3 bright = centre_pixel(scene, settings, {0.0f, 5.0f, 0.0f}, {0.0f, -1.0f, 0.0f}, {0.0f, 0.0f, -1.0f});
    EXPECT_GT(dark.x, 0.0f);
    EXPECT_EQ(bright, dark);
}

}  // namespace
}  // namespace rt
