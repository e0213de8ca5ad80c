// Orthographic cameras: parallel rays from the image plane, an image size that
// does not change with distance but does with ortho_height, motion blur from
// the interpolated pose, one pixel's footprint as the ray cone, the depth layer
// as the distance from the image plane, and the debugger's primary ray where
// the render's is.
#include <cmath>

#include <gtest/gtest.h>

#include "geometry/accel.h"
#include "image/aov.h"
#include "integrator/render.h"
#include "test_scenes.h"

namespace rt {
namespace {

using namespace rt::testing;

Camera ortho(vec3 position, vec3 target, float height) {
    Camera camera = make_camera(position, target);
    camera.set_projection(ORTHOGRAPHIC);
    camera.set_ortho_height(height);
    return camera;
}

// A unit sphere at the origin and a light: what the coverage tests look at.
Scene unit_sphere() {
    Scene scene;
    scene.spheres.push_back({vec3(0.0f), 1.0f, add_material(scene, vec3(0.5f))});
    add_point_light(scene, vec3(0.0f, 0.0f, 50.0f), 100.0f);
    return scene;
}

// The pixels whose primary ray hits something (depth > 0), in a w x h render.
int covered_pixels(const Scene& scene, const Camera& camera, uint32_t w = 64, uint32_t h = 48) {
    const Accelerator accel(scene, 1);
    const Renderer renderer(accel, make_settings(w, h), camera);
    std::vector<float> rgb(size_t(w) * h * 3);
    AuxImage aux(w, h, {DEPTH});
    renderer.render_tile({0, 0, w, h}, rgb.data(), aux.layers());
    int covered = 0;
    for (float depth : aux.depth) covered += depth > 0.0f;
    return covered;
}

TEST(Orthographic, RaysAreParallelAndLeaveFromTheImagePlane) {
    const uint32_t w = 40, h = 20;
    const float height = 3.0f;
    const ViewCamera camera(ortho(vec3(1.0f, 2.0f, 5.0f), vec3(1.0f, 2.0f, 0.0f), height), w, h);
    EXPECT_TRUE(camera.orthographic());
    const Ray centre = camera.generate_ray(0.5f * w, 0.5f * h);
    EXPECT_NEAR(glm::distance(centre.origin, vec3(1.0f, 2.0f, 5.0f)), 0.0f, 1e-6f);
    for (vec2 film : {vec2(0.0f), vec2(float(w), 0.0f), vec2(0.0f, float(h)), vec2(13.5f, 7.25f)}) {
        const Ray ray = camera.generate_ray(film.x, film.y);
        EXPECT_NEAR(glm::distance(ray.direction, vec3(0.0f, 0.0f, -1.0f)), 0.0f, 1e-6f) << film.x << ", " << film.y;
        EXPECT_FLOAT_EQ(ray.origin.z, 5.0f);  // on the plane through the position
    }
    // The height spans ortho_height, the width that times the image's aspect.
    const vec3 top_left = camera.generate_ray(0.0f, 0.0f).origin;
    const vec3 bottom_right = camera.generate_ray(float(w), float(h)).origin;
    EXPECT_NEAR(top_left.y - bottom_right.y, height, 1e-5f);
    EXPECT_NEAR(bottom_right.x - top_left.x, height * float(w) / float(h), 1e-5f);
    // A pinhole's rays, for contrast, fan out from one point.
    const ViewCamera pinhole(make_camera(vec3(1.0f, 2.0f, 5.0f), vec3(1.0f, 2.0f, 0.0f)), w, h);
    EXPECT_FALSE(pinhole.orthographic());
    EXPECT_GT(glm::distance(pinhole.generate_ray(0.0f, 0.0f).direction, pinhole.generate_ray(40.0f, 20.0f).direction),
              0.5f);
}

TEST(Orthographic, ImageSizeDoesNotChangeWithDistance) {
    const Scene scene = unit_sphere();
    const int near = covered_pixels(scene, ortho(vec3(0.0f, 0.0f, 3.0f), vec3(0.0f), 4.0f));
    const int far = covered_pixels(scene, ortho(vec3(0.0f, 0.0f, 300.0f), vec3(0.0f), 4.0f));
    // 48 pixels for 4 units: the unit sphere's radius is 12 pixels, pi r^2 about 452.
    EXPECT_NEAR(near, kPi * 12.0f * 12.0f, 20.0f);
    EXPECT_NEAR(near, far, 2);
    // The same two distances through a pinhole: the far sphere is a speck.
    const int perspective_near = covered_pixels(scene, make_camera(vec3(0.0f, 0.0f, 3.0f), vec3(0.0f)));
    const int perspective_far = covered_pixels(scene, make_camera(vec3(0.0f, 0.0f, 300.0f), vec3(0.0f)));
    EXPECT_GT(perspective_near, 10 * std::max(perspective_far, 1));
}

TEST(Orthographic, ImageSizeFollowsTheOrthoHeight) {
    const Scene scene = unit_sphere();
    const int small = covered_pixels(scene, ortho(vec3(0.0f, 0.0f, 5.0f), vec3(0.0f), 4.0f));
    const int large = covered_pixels(scene, ortho(vec3(0.0f, 0.0f, 5.0f), vec3(0.0f), 8.0f));
    // Twice the height: half the diameter in pixels, a quarter of the area.
    EXPECT_NEAR(float(large) / float(small), 0.25f, 0.03f);
}

TEST(Orthographic, DepthIsTheDistanceFromTheImagePlane) {
    Scene scene;
    add_quad(scene, vec3(-50.0f, -50.0f, -5.0f), vec3(100.0f, 0.0f, 0.0f), vec3(0.0f, 100.0f, 0.0f),
             add_material(scene, vec3(0.5f)));
    add_point_light(scene, vec3(0.0f), 1.0f);
    const Accelerator accel(scene, 1);
    const uint32_t w = 16, h = 12;
    const Renderer renderer(accel, make_settings(w, h), ortho(vec3(0.0f), vec3(0.0f, 0.0f, -1.0f), 10.0f));
    std::vector<float> rgb(size_t(w) * h * 3);
    AuxImage aux(w, h, {DEPTH});
    renderer.render_tile({0, 0, w, h}, rgb.data(), aux.layers());
    for (float depth : aux.depth) EXPECT_NEAR(depth, 5.0f, 1e-5f);
}

TEST(Orthographic, RayConeIsOnePixelWideAndDoesNotSpread) {
    const ViewCamera camera(ortho(vec3(0.0f, 0.0f, 5.0f), vec3(0.0f), 3.0f), 64, 48);
    const RayCone cone = camera.ray_cone();
    EXPECT_EQ(cone.spread, 0.0f);
    EXPECT_FLOAT_EQ(cone.width, 3.0f / 48.0f);
    EXPECT_FLOAT_EQ(cone.width_at(1000.0f), cone.width);
}

TEST(Orthographic, MotionBlurInterpolatesThePose) {
    Camera moving = ortho(vec3(0.0f, 0.0f, 5.0f), vec3(0.0f), 4.0f);
    CameraPose& close = *moving.mutable_shutter_close();
    for (float v : {2.0f, 0.0f, 5.0f}) close.add_position(v);
    for (float v : {2.0f, 0.0f, 0.0f}) close.add_target(v);
    const ViewCamera camera(moving, 64, 48);
    ASSERT_TRUE(camera.moving());
    const ViewCamera halfway(ortho(vec3(1.0f, 0.0f, 5.0f), vec3(1.0f, 0.0f, 0.0f), 4.0f), 64, 48);
    const Ray a = camera.generate_ray(10.0f, 20.0f, 0.5f), b = halfway.generate_ray(10.0f, 20.0f);
    EXPECT_NEAR(glm::distance(a.origin, b.origin), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::distance(a.direction, b.direction), 0.0f, 1e-6f);
    EXPECT_EQ(a.time, 0.5f);

    // FRAMES: the mean of two still frames, at times 1/4 and 3/4.
    const Scene scene = unit_sphere();
    const Accelerator accel(scene, 1);
    RenderSettings settings = make_settings(32, 24);
    settings.set_motion_blur(FRAMES);
    settings.set_motion_frames(2);
    const Renderer blurred(accel, settings, moving);
    const Renderer first(accel, make_settings(32, 24), ortho(vec3(0.5f, 0.0f, 5.0f), vec3(0.5f, 0.0f, 0.0f), 4.0f));
    const Renderer second(accel, make_settings(32, 24), ortho(vec3(1.5f, 0.0f, 5.0f), vec3(1.5f, 0.0f, 0.0f), 4.0f));
    int differs = 0;
    for (uint32_t y = 0; y < 24; y += 3) {
        for (uint32_t x = 0; x < 32; x += 3) {
            const vec3 mean = 0.5f * (render_pixel(first, x, y) + render_pixel(second, x, y));
            const vec3 got = render_pixel(blurred, x, y);
            EXPECT_NEAR(glm::distance(got, mean), 0.0f, 1e-5f) << x << ", " << y;
            differs += glm::distance(render_pixel(first, x, y), render_pixel(second, x, y)) > 1e-3f;
        }
    }
    EXPECT_GT(differs, 0) << "the camera's motion must show";
}

TEST(Orthographic, DebuggerTracesTheRenderPrimaryRay) {
    const Scene scene = unit_sphere();
    const Accelerator accel(scene, 1);
    const Camera camera = ortho(vec3(0.0f, 0.0f, 5.0f), vec3(0.0f), 4.0f);
    const Renderer renderer(accel, make_settings(64, 48), camera);
    const DebugPath path = renderer.debug_pixel(40, 30);
    ASSERT_GT(path.segments_size(), 0);
    const RaySegment& primary = path.segments(0);
    const Ray ray = ViewCamera(camera, 64, 48).generate_ray(40.5f, 30.5f, 0.5f);
    EXPECT_NEAR(glm::distance(vec3(primary.origin(0), primary.origin(1), primary.origin(2)), ray.origin), 0.0f, 1e-6f);
    EXPECT_NEAR(primary.end(0), ray.origin.x, 1e-5f);  // straight down the view direction
    EXPECT_NEAR(primary.end(1), ray.origin.y, 1e-5f);
}

TEST(Orthographic, RefusesAMissingOrBadHeight) {
    Camera camera = make_camera(vec3(0.0f, 0.0f, 5.0f), vec3(0.0f));
    camera.set_projection(ORTHOGRAPHIC);
    const Scene scene = unit_sphere();
    const Accelerator accel(scene, 1);
    const auto message = [&](const Camera& c) {
        try {
            const Renderer renderer(accel, make_settings(8, 8), c);
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    EXPECT_EQ(message(camera), "camera.ortho_height: is required for an ORTHOGRAPHIC camera");
    camera.set_ortho_height(0.0f);
    EXPECT_EQ(message(camera), "camera.ortho_height: 0 is below the minimum 1e-30");
    camera.set_ortho_height(-2.0f);
    EXPECT_EQ(message(camera), "camera.ortho_height: -2 is below the minimum 1e-30");
    camera.set_ortho_height(std::nanf(""));
    EXPECT_EQ(message(camera), "camera.ortho_height: must be a finite number");
    // A perspective camera ignores the height, yet a bad one is still refused.
    camera.set_projection(PERSPECTIVE);
    camera.set_ortho_height(-2.0f);
    EXPECT_EQ(message(camera), "camera.ortho_height: -2 is below the minimum 1e-30");
}

}  // namespace
}  // namespace rt
