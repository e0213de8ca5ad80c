// Whole renders through rt::Renderer of what breaks floating point: grazing
// and in-plane rays, degenerate and sliver triangles, a box collapsing to a
// point, and scenes from 1e-30 to 1e30 in size or far from the origin
// (tests/stability_scenes.h). No pixel may be NaN or infinite.
#include <cmath>

#include <gtest/gtest.h>

#include "stability_probes.h"

namespace rt {
namespace {

using namespace rt::testing;

TEST(StabilityNonFinite, EveryHostileRenderIsFinite) {
    for (const HostileCase& c : hostile_cases())
        EXPECT_EQ(non_finite_pixels(c.scene, c.camera, c.settings, 2), 0u) << c.name;
}

// Finite and also right: the still life, scaled with its light intensities,
// renders the same image wherever the triangle test's float products stay in
// range (triangles vanish beyond about 1e-15 and 1e13; spheres do not).
TEST(StabilityNonFinite, ScalingTheStillLifeLeavesItsImage) {
    const HostileCase reference = still_life("scale_1", 1.0f);
    const Accelerator reference_accel(reference.scene, 2);
    RenderStats stats;
    const Image expected = Renderer(reference_accel, reference.settings, reference.camera).render(2, 16, nullptr, stats);
    for (float scale : {1e-12f, 1e-6f, 1e6f, 1e12f}) {
        const HostileCase scaled = still_life("scaled", scale);
        const Accelerator accel(scaled.scene, 2);
        const Image image = Renderer(accel, scaled.settings, scaled.camera).render(2, 16, nullptr, stats);
        size_t differing = 0;
        for (size_t i = 0; i < image.rgb.size(); ++i)
            differing += !(std::abs(image.rgb[i] - expected.rgb[i]) <= 0.02f * (1.0f + expected.rgb[i]));
        // Rounding moves a few rays across an edge.
        EXPECT_LE(differing, image.rgb.size() / 50) << "scale " << scale;
    }
}

// The loaders drop triangles without area, but a scene built otherwise, or a
// moving triangle at the moment it passes through a line, may still be hit
// by rounding: its surface then faces the ray rather than having no normal.
TEST(StabilityNonFinite, ATriangleWithoutAreaFacesTheRayThatHitIt) {
    const Scene scene = mesh_scene({{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}, {2.0f, 2.0f, 2.0f}}, {{0, 1, 2}});
    const Ray ray{{1.0f, 1.0f, 5.0f}, glm::normalize(vec3(0.1f, 0.2f, -1.0f))};
    const SurfaceHit s = surface_at(scene, ray, Hit{4.0f, 0, 0.25f, 0.25f});
    EXPECT_EQ(s.ng, -ray.direction);
    EXPECT_TRUE(is_finite(s.ns));
}

}  // namespace
}  // namespace rt
