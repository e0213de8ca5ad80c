// Motion blur: a render whose samples each take their own shutter time equals
// the mean of still renders over the shutter interval, within its noise; the
// 2020 report's FRAMES is that mean exactly; a still scene renders as it always did;
// the BVH finds what testing every moving triangle at the ray's time finds.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "geometry/accel.h"
#include "geometry/brute_force.h"
#include "loader_test_util.h"
#include "integrator/render.h"
#include "test_meshes.h"
#include "test_scenes.h"

namespace rt {
namespace {

using namespace rt::testing;

// The scene as it stands at shutter time `time`, still.
Scene scene_at(const Scene& moving, float time) {
    Scene still = moving;
    for (uint32_t v = 0; v < moving.positions.size(); ++v) {
        still.positions[v] = moving.position_at(v, time);
        // Left unnormalised, as surface_at interpolates them.
        still.normals[v] = lerp_position(moving.normals[v], moving.normals_close[v], time);
    }
    still.positions_close.clear();
    still.normals_close.clear();
    return still;
}

vec3 lerp_field(const google::protobuf::RepeatedField<float>& open, const google::protobuf::RepeatedField<float>& close,
                float time) {
    return lerp_position(vec3(open[0], open[1], open[2]), vec3(close[0], close[1], close[2]), time);
}

// The camera as it stands at `time`, still: the pose interpolated as ViewCamera does.
Camera camera_at(const Camera& moving, float time) {
    const CameraPose& close = moving.shutter_close();
    return make_camera(lerp_field(moving.position(), close.position(), time),
                       lerp_field(moving.target(), close.target(), time), moving.fov_y(),
                       lerp_field(moving.up(), close.up(), time));
}

// The 2020 report's demo: the look-at point moves by `shift` along x while the shutter is open.
Camera look_shift(const Camera& camera, float shift) {
    Camera moving = camera;
    CameraPose& close = *moving.mutable_shutter_close();
    for (int i = 0; i < 3; ++i) {
        close.add_position(camera.position(i));
        close.add_target(camera.target(i) + (i == 0 ? shift : 0.0f));
        close.add_up(camera.up(i));
    }
    return moving;
}

RenderSettings settings(uint32_t samples, MotionBlur mode = TIME_SAMPLED, uint32_t frames = 16) {
    RenderSettings s = make_settings(64, 48);
    s.set_samples_per_pixel(samples);
    s.set_motion_blur(mode);
    s.set_motion_frames(frames);
    return s;
}

Image render(const Scene& scene, const Camera& camera, const RenderSettings& s) {
    const Accelerator accel(scene);
    const Renderer renderer(accel, s, camera);
    RenderStats stats;
    return renderer.render(0, 16, nullptr, stats);
}

// The mean of still renders at the centres of `frames` equal parts of the shutter interval.
Image mean_of_stills(const Scene& scene, const Camera& camera, uint32_t frames, uint32_t samples) {
    const RenderSettings s = settings(samples);
    std::vector<double> sum;
    Image mean;
    for (uint32_t f = 0; f < frames; ++f) {
        const float time = (float(f) + 0.5f) / float(frames);
        const Scene still = scene.moving() ? scene_at(scene, time) : scene;
        const Image image = render(still, camera.has_shutter_close() ? camera_at(camera, time) : camera, s);
        if (sum.empty()) sum.assign(image.rgb.size(), 0.0), mean = image;
        for (size_t i = 0; i < sum.size(); ++i) sum[i] += image.rgb[i];
    }
    for (size_t i = 0; i < sum.size(); ++i) mean.rgb[i] = float(sum[i] / frames);
    return mean;
}

double rmse(const Image& a, const Image& b) {
    double sum = 0.0;
    for (size_t i = 0; i < a.rgb.size(); ++i) sum += double(a.rgb[i] - b.rgb[i]) * double(a.rgb[i] - b.rgb[i]);
    return std::sqrt(sum / double(a.rgb.size()));
}

double max_difference(const Image& a, const Image& b) {
    double most = 0.0;
    for (size_t i = 0; i < a.rgb.size(); ++i) most = std::max(most, std::abs(double(a.rgb[i]) - b.rgb[i]));
    return most;
}

// How far a time-sampled render of `samples` per pixel is from its expectation
// (root mean square over the image): half the samples of a render of twice as
// many are the first render's, the other half are independent of them, so the
// two halves differ by about sqrt(2) times the noise of one.
double noise(const Scene& scene, const Camera& camera, uint32_t samples) {
    const Image first = render(scene, camera, settings(samples));
    Image second = render(scene, camera, settings(2 * samples));
    for (size_t i = 0; i < second.rgb.size(); ++i) second.rgb[i] = 2.0f * second.rgb[i] - first.rgb[i];
    return rmse(first, second) / std::sqrt(2.0);
}

const Camera kCloseUp = make_camera(vec3(0.0f, 1.3f, 2.6f), vec3(0.0f, 0.9f, 0.0f), 45.0f);

// A floor and a box that turns by 30 degrees about the vertical axis through
// the origin while sliding by 0.3 along x (an OBJ with its sidecar), lit by a
// point light.
Scene sliding_box() {
    std::string obj = "o floor\nv -3 0 -3\nv -3 0 3\nv 3 0 3\nv 3 0 -3\nvn 0 1 0\nf 1//1 2//1 3//1 4//1\no box\n";
    const Scene cube_mesh = cube();
    for (const vec3& p : cube_mesh.positions) {
        const vec3 q = 0.3f * p + vec3(-0.2f, 0.3f, 0.0f);
        obj += "v " + std::to_string(q.x) + " " + std::to_string(q.y) + " " + std::to_string(q.z) + "\n";
    }
    for (const uvec3& t : cube_mesh.triangles)
        obj += "f " + std::to_string(t[0] + 5) + " " + std::to_string(t[1] + 5) + " " + std::to_string(t[2] + 5) + "\n";
    const TempDir dir;
    dir.write("box.rt.json", R"({"lights": [{"position": [1, 3, 2], "intensity": 8}],
        "motions": [{"node": "box", "translation": [0.3, 0, 0], "rotation": [0, 0.258819, 0, 0.965926]}]})");
    return load_scene(dir.write("box.obj", obj));
}

const Camera kBoxView = make_camera(vec3(0.0f, 1.0f, 1.8f), vec3(0.0f, 0.3f, 0.0f), 45.0f);

// A render of 256 time-sampled samples per pixel is within three times its
// noise of the mean of 32 still renders (of 64 samples per pixel each) over
// the shutter interval. The same render of a motion half as long (`half`) is
// far beyond that: a wrong mapping of the sampled times could not pass.
void expect_mean_of_stills(const Scene& scene, const Camera& camera, const Scene& half, const Camera& half_camera) {
    const uint32_t samples = 256;
    const Image stills = mean_of_stills(scene, camera, 32, 64);
    const double tolerance = 3.0 * noise(scene, camera, samples);
    const double error = rmse(render(scene, camera, settings(samples)), stills);
    const double half_error = rmse(render(half, half_camera, settings(samples)), stills);
    ::testing::Test::RecordProperty("tolerance", std::to_string(tolerance));
    ::testing::Test::RecordProperty("error", std::to_string(error));
    ::testing::Test::RecordProperty("half_motion_error", std::to_string(half_error));
    EXPECT_LE(error, tolerance);
    EXPECT_GT(half_error, 3.0 * tolerance);
}

TEST(MotionBlur, TimeSampledMovingCameraIsTheMeanOfStillRenders) {
    const Scene scene = floor_and_sphere(1.0f);
    expect_mean_of_stills(scene, look_shift(kCloseUp, 0.15f), scene, look_shift(kCloseUp, 0.075f));
}

TEST(MotionBlur, TimeSampledMovingMeshIsTheMeanOfStillRenders) {
    const Scene scene = sliding_box();
    ASSERT_TRUE(scene.moving());
    Scene half = scene;
    for (uint32_t v = 0; v < scene.positions.size(); ++v) {
        half.positions_close[v] = scene.position_at(v, 0.5f);
        half.normals_close[v] = lerp_position(scene.normals[v], scene.normals_close[v], 0.5f);
    }
    expect_mean_of_stills(scene, kBoxView, half, kBoxView);
}

// The 2020 report's method: the mean of whole still renders at the centres of
// motion_frames equal parts of the shutter interval, each of the full
// samples_per_pixel; only float rounding apart from doing it by hand.
TEST(MotionBlur, FramesIsTheMeanOfStillRendersAtTheFrameCentres) {
    const Scene scene = sliding_box();
    const Camera camera = look_shift(kBoxView, 0.15f);
    for (uint32_t samples : {1u, 4u}) {
        const Image frames = render(scene, camera, settings(samples, FRAMES, 5));
        const Image stills = mean_of_stills(scene, camera, 5, samples);
        EXPECT_LE(max_difference(frames, stills), 1e-5) << samples << " samples per pixel";
        EXPECT_GT(rmse(frames, render(scene, camera, settings(samples))), 0.0);  // not the time-sampled image
    }
}

// With nothing moving, both modes render the image of before motion blur
// existed, bit for bit; so do a camera and a motion that end where they start.
TEST(MotionBlur, StillScenesRenderTheSameInEitherMode) {
    const Scene scene = floor_and_sphere(1.0f);
    for (uint32_t samples : {1u, 16u}) {
        RenderSettings defaults = make_settings(64, 48);
        defaults.set_samples_per_pixel(samples);
        const Image plain = render(scene, kCloseUp, defaults);
        EXPECT_EQ(render(scene, kCloseUp, settings(samples, FRAMES, 7)).rgb, plain.rgb);
        EXPECT_EQ(render(scene, kCloseUp, settings(samples, TIME_SAMPLED)).rgb, plain.rgb);
        EXPECT_EQ(render(scene, look_shift(kCloseUp, 0.0f), settings(samples, FRAMES, 7)).rgb, plain.rgb);
    }

    const TempDir dir;
    dir.write("t.rt.json", R"({"motions": [{"node": "tri", "translation": [0, 0, 0]}]})");
    EXPECT_FALSE(load_scene(dir.write("t.obj", "o tri\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")).moving());
}

TEST(MotionBlur, AdaptiveSamplingStopsEarlyAndStillAveragesOverTheShutter) {
    const Scene scene = floor_and_sphere(1.0f);
    const Camera camera = look_shift(kCloseUp, 0.15f);
    RenderSettings adaptive = settings(256);
    adaptive.set_adaptive_threshold(0.05f);
    const Accelerator accel(scene);
    RenderStats stats;
    const Image image = Renderer(accel, adaptive, camera).render(0, 16, nullptr, stats);
    EXPECT_LT(stats.samples, uint64_t(256) * 64 * 48 / 2);
    const Image stills = mean_of_stills(scene, camera, 16, 32);
    // Noisier than 256 samples everywhere, but far nearer the blurred image than the sharp one is.
    EXPECT_LT(rmse(image, stills), rmse(render(scene, kCloseUp, settings(256)), stills) / 10.0);
}

// The debugger traces each sample at the time the render gives it.
TEST(MotionBlur, DebugPathsFollowTheRendersTimes) {
    const Scene scene = sliding_box();
    const Camera camera = look_shift(kBoxView, 0.15f);
    const Accelerator accel(scene);
    for (const RenderSettings& s : {settings(4), settings(4, FRAMES, 3), settings(1)}) {
        const Renderer renderer(accel, s, camera);
        RenderStats stats;
        const Image image = renderer.render(0, 16, nullptr, stats);
        for (uint32_t x : {20u, 32u, 44u}) {
            const DebugPath path = renderer.debug_pixel(x, 30);
            EXPECT_EQ(vec3(path.color(0), path.color(1), path.color(2)), image.pixel(x, 30));
        }
    }
}

TEST(MotionBlur, CameraPosesAreCheckedAtBothEndsAndInBetween) {
    const auto problem = [](const Camera& camera) {
        try {
            ViewCamera(camera, 8, 8);
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    const Camera still = make_camera(vec3(0.0f, 0.0f, 1.0f), vec3(0.0f));
    Camera camera = still;
    CameraPose& close = *camera.mutable_shutter_close();
    for (float v : {0.0f, 0.0f, -1.0f}) close.add_position(v);
    for (float v : {0.0f, 0.0f, -1.0f}) close.add_target(v);
    EXPECT_EQ(problem(camera), "camera.shutter_close: position and target must differ");
    close.set_target(2, -2.0f);
    close.add_up(0.0f), close.add_up(0.0f), close.add_up(1.0f);
    EXPECT_EQ(problem(camera), "camera.shutter_close.up: must not be parallel to the view direction");
    // Each end is fine, but halfway the camera stands on its target.
    close.set_up(1, 1.0f), close.set_up(2, 0.0f), close.set_target(2, 0.0f);
    EXPECT_EQ(problem(camera), "camera.shutter_close: position and target must differ (between the poses, at "
                               "shutter time 0.500000)");
    close.set_target(2, -2.0f);
    EXPECT_EQ(problem(camera), "accepted");
    EXPECT_TRUE(ViewCamera(camera, 8, 8).moving());
    EXPECT_FALSE(ViewCamera(look_shift(still, 0.0f), 8, 8).moving());

    // The schema's limits apply as to the pose at shutter open.
    Camera partial = still;
    partial.mutable_shutter_close()->add_position(1.0f);
    const Scene scene = floor_and_sphere(1.0f);
    const Accelerator accel(scene);
    try {
        Renderer(accel, make_settings(8, 8), partial);
        ADD_FAILURE() << "a pose at shutter close without a target was accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_EQ(std::string(e.what()), "camera.shutter_close.position: needs 3 values, got 1");
    }
}

// The BVH bounds each moving triangle over the whole shutter interval: at any
// time it finds what testing every triangle where it then is finds.
TEST(MotionBlur, BvhMatchesBruteForceAtEveryTime) {
    Scene scene = random_soup(3000, 11);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> offset(-3.0f, 3.0f), unit(0.0f, 1.0f);
    scene.positions_close = scene.positions;
    scene.normals_close = scene.normals;
    // Every other triangle moves (soup triangles share no vertices), some far.
    for (size_t t = 0; t < scene.triangles.size(); t += 2) {
        const vec3 shift(offset(rng), offset(rng), offset(rng));
        for (int k = 0; k < 3; ++k) scene.positions_close[scene.triangles[t][k]] += shift * (t % 6 == 0 ? 3.0f : 1.0f);
    }
    const Accelerator accel(scene);
    int failures = 0;
    size_t hits = 0;
    for (Ray ray : random_rays(scene, 10000, 3)) {
        ray.time = unit(rng);
        const Hit expected = brute_force_hit(scene, ray);
        Hit hit;
        const bool found = accel.intersect(ray, hit);
        hits += found;
        bool same = found == expected.found() && accel.occluded(ray) == found;
        if (same && found)
            same = hit.primitive == expected.primitive ? hit.t == expected.t
                                                       : std::abs(hit.t - expected.t) <= 1e-6f * expected.t;
        if (!same && ++failures <= 5)
            ADD_FAILURE() << "ray at time " << ray.time << ": BVH " << (found ? hit.primitive : kNoPrimitive)
                          << " at t = " << hit.t << ", brute force " << expected.primitive << " at t = " << expected.t;
    }
    EXPECT_EQ(failures, 0);
    EXPECT_GT(hits, 2500u);
}

}  // namespace
}  // namespace rt
