// The denoiser's guides (aov.h): where the camera sees a mirror or glass, the
// albedo and normal layers hold the surface the mirror shows or the glass lets
// through, tinted by them; and the layers are the same whichever path renders
// them (camera-ray packets, or ray by ray with the BVH cost).
#include <gtest/gtest.h>

#include "geometry/accel.h"
#include "image/aov.h"
#include "integrator/render.h"
#include "test_meshes.h"
#include "test_scenes.h"

namespace rt {
namespace {

using namespace rt::testing;

constexpr vec3 kRed(0.8f, 0.1f, 0.1f), kGreen(0.1f, 0.7f, 0.2f);

// The camera at the origin looks down -z at a 4 x 4 square at z = -2 of
// `front`; behind it, at z = -5, a green wall; behind the camera, at z = 3, a
// red one. A point light between the camera and the square.
Scene square_between_walls(uint32_t (*front)(Scene&)) {
    Scene scene;
    const uint32_t red = add_material(scene, kRed), green = add_material(scene, kGreen);
    add_quad(scene, vec3(-2.0f, -2.0f, -2.0f), vec3(4.0f, 0.0f, 0.0f), vec3(0.0f, 4.0f, 0.0f), front(scene));
    add_quad(scene, vec3(-20.0f, -20.0f, -5.0f), vec3(40.0f, 0.0f, 0.0f), vec3(0.0f, 40.0f, 0.0f), green);
    add_quad(scene, vec3(-20.0f, -20.0f, 3.0f), vec3(0.0f, 40.0f, 0.0f), vec3(40.0f, 0.0f, 0.0f), red);
    add_point_light(scene, vec3(0.0f, 1.0f, -1.0f), 5.0f);
    return scene;
}

struct Guides {
    vec3 albedo, normal;
};

Guides centre_guides(const Scene& scene) {
    const Accelerator accel(scene, 1);
    const Renderer renderer(accel, make_settings(9, 9), make_camera(vec3(0.0f), vec3(0.0f, 0.0f, -1.0f), 20.0f));
    std::vector<float> rgb(3);
    AuxImage aux(1, 1, {ALBEDO, NORMAL});
    renderer.render_tile({4, 4, 1, 1}, rgb.data(), aux.layers());
    return {vec3(aux.albedo[0], aux.albedo[1], aux.albedo[2]), vec3(aux.normal[0], aux.normal[1], aux.normal[2])};
}

TEST(DenoiseGuides, AMirrorShowsTheAlbedoAndNormalOfWhatItReflects) {
    const Guides mirror = centre_guides(square_between_walls([](Scene& s) {
        return add_material(s, vec3(0.0f), vec3(0.0f), 1.0f, vec3(0.9f));
    }));
    // The red wall behind the camera, seen by a ray going +z, tinted by the mirror.
    EXPECT_NEAR(glm::distance(mirror.albedo, 0.9f * kRed), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::distance(mirror.normal, vec3(0.0f, 0.0f, -1.0f)), 0.0f, 1e-5f);
}

TEST(DenoiseGuides, GlassShowsTheSurfaceBehindIt) {
    const Guides glass = centre_guides(square_between_walls([](Scene& s) {
        const uint32_t m = add_material(s, vec3(0.0f));
        s.materials[m].transmission = vec3(1.0f);
        return m;
    }));
    // Head-on, Fresnel reflects 4% at n = 1.5; the rest reaches the green wall.
    EXPECT_NEAR(glm::distance(glass.albedo, 0.96f * kGreen), 0.0f, 1e-3f);
    EXPECT_NEAR(glm::distance(glass.normal, vec3(0.0f, 0.0f, 1.0f)), 0.0f, 1e-5f);
}

TEST(DenoiseGuides, AMostlyDiffuseSurfaceKeepsItsOwn) {
    const Guides satin = centre_guides(square_between_walls([](Scene& s) {
        return add_material(s, vec3(0.6f), vec3(0.0f), 1.0f, vec3(0.3f));
    }));
    EXPECT_EQ(satin.albedo, vec3(0.6f));
    EXPECT_NEAR(glm::distance(satin.normal, vec3(0.0f, 0.0f, 1.0f)), 0.0f, 1e-5f);
}

// The Cornell box's mirror camera at 4 samples a pixel: camera-ray packets
// render the layers without the BVH cost, ray by ray with it.
TEST(DenoiseGuides, PacketsAndSingleRaysGiveTheSameLayers) {
    const Scene scene = sample_scene("cornell.obj");
    const Accelerator accel(scene);
    ASSERT_TRUE(accel.packets_serve());
    RenderSettings settings = make_settings(40, 30);
    settings.set_samples_per_pixel(4);
    const Renderer renderer(accel, settings, scene.cameras.back().camera);
    std::vector<float> packets(40 * 30 * 3), single(40 * 30 * 3);
    AuxImage by_packets(40, 30, {DEPTH, NORMAL, ALBEDO}), by_ray(40, 30, {DEPTH, NORMAL, ALBEDO, BVH_COST});
    renderer.render_tile({0, 0, 40, 30}, packets.data(), by_packets.layers());
    renderer.render_tile({0, 0, 40, 30}, single.data(), by_ray.layers());
    EXPECT_EQ(packets, single);
    EXPECT_EQ(by_packets.depth, by_ray.depth);
    EXPECT_EQ(by_packets.normal, by_ray.normal);
    EXPECT_EQ(by_packets.albedo, by_ray.albedo);
}

}  // namespace
}  // namespace rt
