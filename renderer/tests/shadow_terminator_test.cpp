// The shadow terminator (geometry/shadow_terminator.h): a low-poly sphere
// with smooth normals, lit at a grazing angle, must not show dark facets on
// its lit side where the analytic sphere is lit. Without the fix its shadow
// rays leave the flat facets below the round surface the normals describe
// and hit the neighbouring facets.
#include <gtest/gtest.h>

#include "geometry/accel.h"
#include "geometry/shadow_terminator.h"
#include "integrator/render.h"
#include "instancing_scenes.h"
#include "test_meshes.h"
#include "test_scenes.h"

namespace rt {
namespace {

using namespace rt::testing;

constexpr uint32_t kSize = 160;

// The sphere of radius 1 at the origin under a sun from `to_light`, seen
// from +z; the mesh gets its vertices' sphere normals. A faint emission tells
// a shadowed surface (never quite black) from the background (black).
Scene lit_sphere(bool mesh, vec3 to_light) {
    Scene scene;
    if (mesh) {
        scene = icosphere(1);  // 80 facets
        for (size_t v = 0; v < scene.positions.size(); ++v) scene.normals[v] = glm::normalize(scene.positions[v]);
        scene.materials[0].diffuse = vec3(0.8f);
    } else {
        scene.spheres.push_back({vec3(0.0f), 1.0f, add_material(scene, vec3(0.8f))});
    }
    scene.materials[0].emission = vec3(1e-4f);
    Light sun;
    sun.kind = DIRECTIONAL;
    sun.direction = -glm::normalize(to_light);
    sun.intensity = vec3(3.0f);
    scene.lights.push_back(sun);
    return scene;
}

struct DarkCount {
    int lit = 0;   // pixels whose shading normal faces the light by more than kLitCos
    int dark = 0;  // of those, the ones shown at less than half their unshadowed shading
};

constexpr float kLitCos = 0.1f;

// Every pixel against the same shading without shadows, Kd / pi E cos(ns, wi)
// at the pixel's own hit (its debug path gives the shading normal): on a
// convex sphere nothing may shadow anything, so a pixel much darker than that
// is a facet shadowing its neighbour.
DarkCount dark_pixels(const Scene& scene, vec3 to_light) {
    const Accelerator accel(scene, 1);
    const Renderer renderer(accel, make_settings(kSize, kSize), make_camera({0.0f, 0.0f, 6.0f}, vec3(0.0f), 22.0f));
    std::vector<float> rgb(size_t(kSize) * kSize * 3);
    renderer.render_tile({0, 0, kSize, kSize}, rgb.data());
    const vec3 wi = glm::normalize(to_light);
    DarkCount count;
    for (uint32_t y = 0; y < kSize; ++y)
        for (uint32_t x = 0; x < kSize; ++x) {
            const DebugPath path = renderer.debug_pixel(x, y);
            if (path.segments_size() == 0 || path.segments(0).normal_size() != 3) continue;  // background
            const auto& n = path.segments(0).normal();
            const float cos_theta = glm::dot(vec3(n[0], n[1], n[2]), wi);
            if (!(cos_theta > kLitCos)) continue;
            ++count.lit;
            const float unshadowed = 0.8f / kPi * 3.0f * cos_theta;
            if (rgb[(size_t(y) * kSize + x) * 3] < 0.5f * unshadowed) ++count.dark;
        }
    return count;
}

TEST(ShadowTerminator, LowPolySphereHasNoDarkFacetsNearTheTerminator) {
    // Grazing: the terminator crosses the visible disc.
    for (vec3 to_light : {vec3(1.0f, 0.3f, 0.35f), vec3(-0.8f, 0.5f, 0.2f), vec3(0.2f, -1.0f, 0.3f)}) {
        SCOPED_TRACE("light from (" + std::to_string(to_light.x) + ", " + std::to_string(to_light.y) + ", " +
                     std::to_string(to_light.z) + ")");
        const DarkCount mesh = dark_pixels(lit_sphere(true, to_light), to_light);
        EXPECT_GT(mesh.lit, 3000);
        EXPECT_LE(mesh.dark, mesh.lit / 200) << mesh.dark << " of " << mesh.lit << " lit pixels are dark";
        // The analytic sphere, which has no facets, passes the same count.
        const DarkCount sphere = dark_pixels(lit_sphere(false, to_light), to_light);
        EXPECT_GT(sphere.lit, 3000);
        EXPECT_EQ(sphere.dark, 0);
    }
}

// The offset lifts points of a facet onto the round surface and no further:
// on a flat (or concave) neighbourhood it leaves the point alone.
TEST(ShadowTerminator, OffsetOnlyLiftsConvexFacets) {
    Scene scene = icosphere(0);
    for (size_t v = 0; v < scene.positions.size(); ++v) scene.normals[v] = glm::normalize(scene.positions[v]);
    Hit hit;
    hit.primitive = 0;
    hit.u = hit.v = 1.0f / 3.0f;
    const uvec3 tri = scene.triangles[0];
    SurfaceHit s;
    s.p = (scene.positions[tri.x] + scene.positions[tri.y] + scene.positions[tri.z]) / 3.0f;
    const float depth = 1.0f - glm::length(s.p);  // how far the facet's centre lies inside the sphere
    const ShadowOrigin lifted = shadow_terminator_origin(scene, hit, s, 1.0f);
    EXPECT_GT(glm::length(lifted.p), glm::length(s.p) + 0.5f * depth);
    // Below all three tangent planes: p' = p + sum b_i (1 - p . n_i) n_i, the
    // blend of its projections onto them (which, on so coarse a mesh, lies
    // outside the sphere: the tangent planes do).
    vec3 expected = s.p;
    for (int k = 0; k < 3; ++k) {
        const vec3 n = scene.normals[tri[k]];
        expected += (1.0f / 3.0f) * (1.0f - glm::dot(s.p, n)) * n;
    }
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(lifted.p[k], expected[k], 1e-6f);
    // Seen from inside (the normals' other side) the surface is concave: no lift.
    EXPECT_EQ(shadow_terminator_origin(scene, hit, s, -1.0f).p, s.p);
    // Flat shading (every normal the facet's) leaves the point where it is.
    const vec3 ng = glm::normalize(glm::cross(scene.positions[tri.y] - scene.positions[tri.x],
                                              scene.positions[tri.z] - scene.positions[tri.x]));
    for (int k = 0; k < 3; ++k) scene.normals[tri[k]] = ng;
    EXPECT_LT(glm::length(shadow_terminator_origin(scene, hit, s, 1.0f).p - s.p), 1e-6f);
}

// The integrator hands shadow_terminator_origin the corners surface_at found
// (an instance's cost a transform to make): the origin is the one they give
// when found again, for instances moving and still and world-space triangles.
TEST(ShadowTerminator, CornersFromSurfaceAtGiveTheSameOrigin) {
    const Scene scene = moving_instanced_soup(40, 7, 0.5f);
    const Accelerator accel(scene, 2);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    uint32_t instanced = 0, world = 0;
    for (int i = 0; i < 4000; ++i) {
        Ray ray{vec3(0.0f, 0.0f, 30.0f), glm::normalize(vec3(0.4f * unit(rng), 0.4f * unit(rng), -1.0f))};
        ray.time = 0.5f * (unit(rng) + 1.0f);
        Hit hit;
        if (!accel.intersect(ray, hit) || hit.primitive >= scene.triangles.size()) continue;
        (hit.instance == kNoInstance ? world : instanced) += 1;
        TriangleCorners corners;
        const SurfaceHit s = surface_at(scene, ray, hit, &corners);
        for (float side : {1.0f, -1.0f}) {
            const ShadowOrigin given = shadow_terminator_origin(scene, hit, s, side, &corners);
            const ShadowOrigin found = shadow_terminator_origin(scene, hit, s, side);
            ASSERT_EQ(given.p, found.p);
            ASSERT_EQ(given.p_error, found.p_error);
        }
    }
    EXPECT_GT(instanced, 500u);
    EXPECT_GT(world, 50u);
}

}  // namespace
}  // namespace rt
