#include "geometry/sphere.h"

#include <random>

#include <gtest/gtest.h>

#include "geometry/spawn.h"

namespace rt {
namespace {

TEST(Sphere, NearestRootFromOutsideAndInside) {
    const Sphere s{{0.0f, 0.0f, -5.0f}, 1.0f, 0};
    float t = 0.0f;
    ASSERT_TRUE(intersect_sphere(Ray{{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f}, kInfinity}, s, t));
    EXPECT_FLOAT_EQ(t, 4.0f);
    ASSERT_TRUE(intersect_sphere(Ray{{0.0f, 0.0f, -5.0f}, {0.0f, 0.0f, -1.0f}, kInfinity}, s, t));
    EXPECT_FLOAT_EQ(t, 1.0f);
    EXPECT_FALSE(intersect_sphere(Ray{{0.0f, 2.0f, 0.0f}, {0.0f, 0.0f, -1.0f}, kInfinity}, s, t));
    EXPECT_FALSE(intersect_sphere(Ray{{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -1.0f}, 3.9f}, s, t));
}

TEST(Sphere, TangentRayHits) {
    const Sphere s{{0.0f, 0.0f, 0.0f}, 1.0f, 0};
    float t = 0.0f;
    EXPECT_TRUE(intersect_sphere(Ray{{1.0f, 0.0f, 5.0f}, {0.0f, 0.0f, -1.0f}, kInfinity}, s, t));
}

// Rays leaving a sphere outwards never hit it again; rays going inwards hit the
// far side, not the near one, at every scale.
TEST(Sphere, SpawnedRaysDoNotSelfIntersect) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    for (float scale : {1e-4f, 1.0f, 1e5f}) {
        const Sphere s{vec3(0.3f, -2.0f, 1.0f) * scale, 0.7f * scale, 0};
        int errors = 0;
        for (int i = 0; i < 5000; ++i) {
            const vec3 dir = glm::normalize(vec3(unit(rng), unit(rng), unit(rng)));
            const Ray probe{s.center - dir * (3.0f * scale), dir, kInfinity};
            float t = 0.0f;
            if (!intersect_sphere(probe, s, t)) continue;
            vec3 error, n;
            const vec3 p = sphere_point(s, probe, t, error, n);
            vec3 out = glm::normalize(n + 0.9f * vec3(unit(rng), unit(rng), unit(rng)));
            if (glm::dot(out, n) <= 0.0f) out = n;
            float t2 = 0.0f;
            errors += intersect_sphere(spawn_ray(p, error, n, out, 0.0f), s, t2);
            const Ray inward = spawn_ray(p, error, n, -out, 0.0f);
            // The far side lies 2 r cos(theta) away; the near side would be at ~0.
            const float chord = 2.0f * s.radius * glm::dot(out, n);
            if (!intersect_sphere(inward, s, t2) || std::abs(t2 - chord) > 1e-3f * s.radius) ++errors;
        }
        EXPECT_EQ(errors, 0) << "scale " << scale;
    }
}

}  // namespace
}  // namespace rt
