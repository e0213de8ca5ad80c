// Mirrors facing each other and glass inside glass between them: a camera
// ray's tree of reflections and refractions stops at max_depth, and at any
// depth min_contribution lets through fewer rays than 1 / min_contribution,
// so that even max_depth 64 renders quickly.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <utility>

#include "loader_test_util.h"
#include "util/proto_limits.h"
#include "stability_probes.h"

namespace rt {
namespace {

using namespace rt::testing;

RenderSettings depth_settings(uint32_t max_depth, float min_contribution) {
    RenderSettings settings = make_settings(16, 16);
    settings.set_max_depth(max_depth);
    settings.set_min_contribution(min_contribution);
    return settings;
}

// With reflectance 1 nothing is cut: every camera ray bounces to max_depth,
// one reflection and one shadow ray per hit.
TEST(StabilityDepthBound, FacingMirrorsBounceExactlyToMaxDepth) {
    const DepthScene mirrors = facing_mirrors();
    for (uint32_t max_depth : {0u, 1u, 5u, 64u}) {
        const DepthRun run = trace_depth(mirrors.scene, mirrors.camera, depth_settings(max_depth, 0.0f));
        EXPECT_EQ(run.most_closest_rays, max_depth + 1);
        EXPECT_EQ(run.most_shadow_rays, max_depth + 1);
    }
}

// Without a cutoff the tree is binary and only max_depth stops it.
TEST(StabilityDepthBound, NestedGlassStopsAtMaxDepthWithoutACutoff) {
    const DepthScene glass = nested_glass_between_mirrors();
    for (uint32_t max_depth : {1u, 4u, 8u, 12u}) {
        const DepthRun run = trace_depth(glass.scene, glass.camera, depth_settings(max_depth, 0.0f));
        EXPECT_GT(run.most_closest_rays, max_depth + 1) << max_depth;  // it does branch
        EXPECT_LE(double(run.most_closest_rays), closest_rays_bound(max_depth, 0.0f, glass.branches)) << max_depth;
    }
}

// At max_depth 64 the default cutoff bounds the tree, also for glass that is
// a mirror too (MTL's illum 7), whose rays' weights would add up to 1.9 at
// every hit if the mirror kept its full reflectance over the glass.
TEST(StabilityDepthBound, MaxDepth64FinishesWithinTheCutoffsBound) {
    for (const DepthScene& d : depth_scenes()) {
        RenderSettings settings = make_settings(16, 16);
        settings.set_max_depth(64);
        apply_limits(settings, "settings");
        const DepthRun run = trace_depth(d.scene, d.camera, settings);
        const double bound = closest_rays_bound(64, settings.min_contribution(), d.branches);
        EXPECT_LE(double(run.most_closest_rays), bound) << d.name;
        // The ray counts are the bound; this only says the bound is small. A
        // tree doubling at each of 64 depths would take years; a minute leaves
        // room for a sanitizer build on a busy 2-core machine.
        EXPECT_LT(run.seconds, 60.0) << d.name;
    }
}

// Settings under which glass could split a camera ray into more rays than
// finish in a second are refused when the renderer is made, naming both
// settings, instead of rendering for years; mirrors alone never split.
TEST(StabilityDepthBound, SettingsThatWouldNeverFinishAreRefused) {
    const DepthScene glass = nested_glass_between_mirrors();
    const Accelerator accel(glass.scene, 1);
    for (const auto& [max_depth, min_contribution] : {std::pair{64u, 0.0f}, {64u, 1e-7f}, {20u, 0.0f}}) {
        try {
            const Renderer renderer(accel, depth_settings(max_depth, min_contribution), glass.camera);
            ADD_FAILURE() << "max_depth " << max_depth << ", min_contribution " << min_contribution << " accepted";
        } catch (const std::invalid_argument& e) {
            const std::string message = e.what();
            EXPECT_NE(message.find("settings.max_depth: " + std::to_string(max_depth)), std::string::npos) << message;
            EXPECT_NE(message.find("settings.min_contribution"), std::string::npos) << message;
        }
    }
    for (const auto& [max_depth, min_contribution] : {std::pair{64u, 0.001f}, {19u, 0.0f}, {64u, 1e-4f}})
        EXPECT_NO_THROW(Renderer(accel, depth_settings(max_depth, min_contribution), glass.camera))
            << max_depth << " " << min_contribution;
    const DepthScene mirrors = facing_mirrors();
    const Accelerator mirror_accel(mirrors.scene, 1);
    EXPECT_NO_THROW(Renderer(mirror_accel, depth_settings(64, 0.0f), mirrors.camera));
}

// Ks above 1 is a lobe weight; as a mirror it would return more light than it gets.
TEST(StabilityDepthBound, MtlMirrorReflectanceIsCappedAtOne) {
    TempDir dir;
    dir.write("m.mtl", "newmtl shiny\nKs 5 0.5 1\nillum 3\n");
    const Scene scene = load_scene(dir.write("m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl shiny\nf 1 2 3\n"));
    ASSERT_EQ(scene.materials.size(), 1u);
    EXPECT_EQ(scene.materials[0].reflectance, vec3(1.0f, 0.5f, 1.0f));
    EXPECT_EQ(scene.materials[0].specular, vec3(5.0f, 0.5f, 1.0f));
}

}  // namespace
}  // namespace rt
