// Rays aimed exactly at the edges and vertices of closed meshes: through the
// accelerator's watertight test, a million of them all stop at the surface,
// from outside and from inside. The plain Möller-Trumbore test lets some of
// the same rays through, so the rays do find leaks where there are any.
#include <gtest/gtest.h>

#include "stability_probes.h"

namespace rt {
namespace {

using namespace rt::testing;

TEST(StabilityEdgeLeaks, AMillionRaysAtEdgesAndVerticesNeverLeak) {
    constexpr size_t kTotalRays = 1000000;
    const std::vector<NamedMesh> meshes = closed_meshes();
    size_t traced = 0;
    for (size_t i = 0; i < meshes.size(); ++i) {
        const Accelerator accel(meshes[i].scene);
        const size_t count = kTotalRays / meshes.size() + (i < kTotalRays % meshes.size());
        const std::vector<Ray> rays = edge_and_vertex_rays(meshes[i].scene, count, uint32_t(i + 1));
        EXPECT_EQ(watertight_leaks(accel, rays), 0u) << meshes[i].name;
        traced += rays.size();
    }
    EXPECT_EQ(traced, kTotalRays);
}

TEST(StabilityEdgeLeaks, MollerTrumboreLeaksOnTheSameKindOfRays) {
    for (const NamedMesh& mesh : closed_meshes()) {
        const Accelerator accel(mesh.scene);
        const std::vector<Ray> rays = edge_and_vertex_rays(mesh.scene, 20000, 99);
        EXPECT_GT(moller_trumbore_leaks(accel, rays), rays.size() / 1000) << mesh.name;
        EXPECT_EQ(watertight_leaks(accel, rays), 0u) << mesh.name;
    }
}

// The rays cross the surface at their point rather than graze it: started a
// little before the point, each meets the mesh there.
TEST(StabilityEdgeLeaks, RaysCrossTheSurfaceAtTheirPoint) {
    for (const NamedMesh& mesh : closed_meshes()) {
        const Accelerator accel(mesh.scene);
        const float size = glm::length(mesh.scene.bounds().extent());
        for (Ray ray : edge_and_vertex_rays(mesh.scene, 2000, 7)) {
            const float length = ray.t_max / 1.001f;  // the distance to the aimed-at point
            ray.origin = ray.at(length - 1e-4f * size);
            ray.t_max = 2e-4f * size;
            Hit hit;
            ASSERT_TRUE(accel.intersect(ray, hit)) << mesh.name;
            EXPECT_NEAR(hit.t, 1e-4f * size, 1e-6f * size) << mesh.name;
        }
    }
}

}  // namespace
}  // namespace rt
