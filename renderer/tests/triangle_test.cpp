#include "geometry/triangle.h"

#include <random>

#include <gtest/gtest.h>

#include "geometry/spawn.h"

namespace rt {
namespace {

const vec3 kA(0.0f, 0.0f, 0.0f), kB(1.0f, 0.0f, 0.0f), kC(0.0f, 1.0f, 0.0f);

bool hits(vec3 origin, vec3 direction, vec3 a = kA, vec3 b = kB, vec3 c = kC, TriangleHit* out = nullptr) {
    TriangleHit hit{};
    const bool found = intersect_triangle(Ray{origin, direction, kInfinity}, a, b, c, hit);
    if (out) *out = hit;
    return found;
}

TEST(Triangle, HitsInteriorWithDistanceAndBarycentrics) {
    TriangleHit hit{};
    ASSERT_TRUE(hits({0.25f, 0.5f, 2.0f}, {0.0f, 0.0f, -1.0f}, kA, kB, kC, &hit));
    EXPECT_FLOAT_EQ(hit.t, 2.0f);
    EXPECT_FLOAT_EQ(hit.u, 0.25f);  // weight of B
    EXPECT_FLOAT_EQ(hit.v, 0.5f);   // weight of C
}

TEST(Triangle, HitsFromBehindToo) {
    EXPECT_TRUE(hits({0.25f, 0.25f, -1.0f}, {0.0f, 0.0f, 1.0f}));
}

TEST(Triangle, MissesOutside) {
    EXPECT_FALSE(hits({0.6f, 0.6f, 1.0f}, {0.0f, 0.0f, -1.0f}));
    EXPECT_FALSE(hits({-0.01f, 0.5f, 1.0f}, {0.0f, 0.0f, -1.0f}));
}

TEST(Triangle, HitsExactlyOnEdgesAndVertices) {
    for (vec3 p : {kA, kB, kC, vec3(0.5f, 0.0f, 0.0f), vec3(0.0f, 0.5f, 0.0f), vec3(0.5f, 0.5f, 0.0f)})
        EXPECT_TRUE(hits(p + vec3(0.0f, 0.0f, 1.0f), {0.0f, 0.0f, -1.0f})) << p.x << ", " << p.y;
}

// Two triangles sharing the diagonal of a quad: a ray exactly through the shared
// edge must hit at least one of them, whatever the ray's direction.
TEST(Triangle, SharedEdgeDoesNotLeak) {
    const vec3 p0(-0.3f, -0.7f, 0.1f), p1(1.3f, -0.2f, -0.2f), p2(1.1f, 0.9f, 0.3f), p3(-0.4f, 1.2f, 0.0f);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    int leaks = 0;
    for (int i = 0; i < 20000; ++i) {
        const float s = unit(rng);
        const vec3 on_edge = p0 + s * (p2 - p0);
        const vec3 origin = on_edge + vec3(unit(rng) - 0.5f, unit(rng) - 0.5f, 1.0f + unit(rng)) * 3.0f;
        const vec3 direction = glm::normalize(on_edge - origin);
        TriangleHit h{};
        const Ray ray{origin, direction, kInfinity};
        if (!intersect_triangle(ray, p0, p1, p2, h) && !intersect_triangle(ray, p0, p2, p3, h)) ++leaks;
    }
    EXPECT_EQ(leaks, 0);
}

TEST(Triangle, SharedVertexDoesNotLeak) {
    // A fan of triangles around a vertex: rays aimed at the vertex hit one of them.
    const vec3 center(0.1f, 0.2f, 0.3f);
    std::vector<vec3> ring;
    for (int k = 0; k < 7; ++k) {
        const float a = 2.0f * kPi * float(k) / 7.0f;
        ring.push_back(center + vec3(std::cos(a), std::sin(a), 0.05f * float(k % 2)));
    }
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    int leaks = 0;
    for (int i = 0; i < 5000; ++i) {
        const vec3 origin = center + vec3(unit(rng), unit(rng), 2.0f + unit(rng));
        const Ray ray{origin, glm::normalize(center - origin), kInfinity};
        bool hit = false;
        for (int k = 0; k < 7; ++k) {
            TriangleHit h{};
            hit |= intersect_triangle(ray, center, ring[k], ring[(k + 1) % 7], h);
        }
        leaks += !hit;
    }
    EXPECT_EQ(leaks, 0);
}

TEST(Triangle, RayParallelToTheTriangleMisses) {
    EXPECT_FALSE(hits({-1.0f, 0.25f, 0.0f}, {1.0f, 0.0f, 0.0f}));  // in its plane
    EXPECT_FALSE(hits({-1.0f, 0.25f, 0.5f}, {1.0f, 0.0f, 0.0f}));  // above its plane
}

TEST(Triangle, DegenerateTrianglesAreNeverHit) {
    const vec3 d(0.0f, 0.0f, -1.0f);
    EXPECT_FALSE(hits({0.5f, 0.0f, 1.0f}, d, kA, kB, vec3(2.0f, 0.0f, 0.0f)));  // collinear
    EXPECT_FALSE(hits({0.0f, 0.0f, 1.0f}, d, kA, kA, kA));                      // a point
    EXPECT_EQ(doubled_area(kA, kB, vec3(2.0f, 0.0f, 0.0f)), 0.0f);
}

TEST(Triangle, RespectsTMax) {
    TriangleHit h{};
    EXPECT_FALSE(intersect_triangle(Ray{{0.2f, 0.2f, 2.0f}, {0.0f, 0.0f, -1.0f}, 1.999f}, kA, kB, kC, h));
    EXPECT_TRUE(intersect_triangle(Ray{{0.2f, 0.2f, 2.0f}, {0.0f, 0.0f, -1.0f}, 2.001f}, kA, kB, kC, h));
}

TEST(Triangle, RayStartingOnTheSurfaceDoesNotHitIt) {
    EXPECT_FALSE(hits({0.25f, 0.25f, 0.0f}, glm::normalize(vec3(0.3f, 0.1f, 1.0f))));
    EXPECT_FALSE(hits({0.25f, 0.25f, 0.0f}, glm::normalize(vec3(0.3f, 0.1f, -1.0f))));
}

// Rays spawned from computed hit points, at every scale, never re-hit their own
// triangle, in either direction.
TEST(Spawn, OffsetOriginsNeverSelfIntersect) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    for (float scale : {1e-4f, 1.0f, 1e5f}) {
        int self_hits = 0;
        for (int i = 0; i < 20000; ++i) {
            const vec3 offset = vec3(unit(rng), unit(rng), unit(rng)) * scale * 10.0f;
            const vec3 a = offset + vec3(unit(rng), unit(rng), unit(rng)) * scale;
            const vec3 b = offset + vec3(unit(rng), unit(rng), unit(rng)) * scale;
            const vec3 c = offset + vec3(unit(rng), unit(rng), unit(rng)) * scale;
            const vec3 n = glm::normalize(glm::cross(b - a, c - a));
            const vec3 origin = offset + vec3(unit(rng), unit(rng), unit(rng)) * scale * 3.0f;
            const vec3 target = a + 0.3f * (b - a) + 0.3f * (c - a);
            TriangleHit hit{};
            if (!intersect_triangle(Ray{origin, glm::normalize(target - origin), kInfinity}, a, b, c, hit)) continue;
            const float b0 = 1.0f - hit.u - hit.v;
            const vec3 p = b0 * a + hit.u * b + hit.v * c;
            const vec3 error = gamma_bound(7) * (glm::abs(b0 * a) + glm::abs(hit.u * b) + glm::abs(hit.v * c));
            for (float side : {1.0f, -1.0f}) {
                vec3 w = glm::normalize(n * side + 0.9f * vec3(unit(rng), unit(rng), unit(rng)));
                if (glm::dot(w, n) * side <= 0.0f) w = n * side;
                TriangleHit again{};
                self_hits += intersect_triangle(spawn_ray(p, error, n, w, 0.0f), a, b, c, again);
            }
        }
        EXPECT_EQ(self_hits, 0) << "scale " << scale;
    }
}

TEST(Spawn, NextFloatStepsOneUlp) {
    EXPECT_GT(next_float_up(1.0f), 1.0f);
    EXPECT_EQ(next_float_down(next_float_up(1.0f)), 1.0f);
    EXPECT_GT(next_float_up(-0.0f), 0.0f);
    EXPECT_LT(next_float_down(0.0f), 0.0f);
}

}  // namespace
}  // namespace rt
