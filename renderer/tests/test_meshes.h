// Meshes and rays built in code for the BVH and accelerator tests: random
// soups, closed meshes whose edges and vertices rays can aim at, sample scenes.
#pragma once

#include <algorithm>
#include <filesystem>
#include <random>
#include <stdexcept>
#include <vector>

#include "load/loader.h"
#include "util/bounds.h"
#include "util/ray.h"
#include "geometry/scene.h"

namespace rt::testing {

inline Scene mesh_scene(std::vector<vec3> positions, std::vector<uvec3> triangles) {
    Scene scene;
    scene.normals.assign(positions.size(), vec3(0.0f, 0.0f, 1.0f));
    scene.positions = std::move(positions);
    scene.triangle_materials.assign(triangles.size(), 0);
    scene.triangles = std::move(triangles);
    scene.materials.emplace_back();
    return scene;
}

inline Scene random_soup(size_t count, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> position(-10.0f, 10.0f);
    std::uniform_real_distribution<float> offset(-1.5f, 1.5f);
    std::vector<vec3> positions;
    std::vector<uvec3> triangles;
    for (uint32_t i = 0; i < count; ++i) {
        const vec3 center(position(rng), position(rng), position(rng));
        for (int k = 0; k < 3; ++k) positions.push_back(center + vec3(offset(rng), offset(rng), offset(rng)));
        triangles.emplace_back(3 * i, 3 * i + 1, 3 * i + 2);
    }
    return mesh_scene(std::move(positions), std::move(triangles));
}

// A closed sphere: the icosahedron with each triangle split in four, `levels` times.
inline Scene icosphere(int levels, float radius = 1.0f) {
    const float g = (1.0f + std::sqrt(5.0f)) / 2.0f;
    std::vector<vec3> positions = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                                   {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
    std::vector<uvec3> triangles = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                                    {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                                    {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    for (vec3& p : positions) p = radius * glm::normalize(p);
    for (int level = 0; level < levels; ++level) {
        std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoints;
        auto midpoint = [&](uint32_t a, uint32_t b) {
            const auto [it, added] = midpoints.try_emplace({std::min(a, b), std::max(a, b)}, uint32_t(positions.size()));
            if (added) positions.push_back(radius * glm::normalize(positions[a] + positions[b]));
            return it->second;
        };
        std::vector<uvec3> split;
        for (const uvec3& t : triangles) {
            const uint32_t ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
            split.insert(split.end(), {{t[0], ab, ca}, {t[1], bc, ab}, {t[2], ca, bc}, {ab, bc, ca}});
        }
        triangles = std::move(split);
    }
    return mesh_scene(std::move(positions), std::move(triangles));
}

// The cube [-1, 1]^3, each face split along a diagonal.
inline Scene cube() {
    std::vector<vec3> positions;
    for (int i = 0; i < 8; ++i) positions.emplace_back(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1);
    const std::vector<uvec3> triangles = {{0, 1, 3}, {0, 3, 2}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                                          {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 3, 7}, {1, 7, 5}};
    return mesh_scene(std::move(positions), triangles);
}

// An n x n grid of unit squares in the plane z = 0, two triangles each.
inline Scene grid(uint32_t n) {
    std::vector<vec3> positions;
    std::vector<uvec3> triangles;
    for (uint32_t y = 0; y <= n; ++y)
        for (uint32_t x = 0; x <= n; ++x) positions.emplace_back(float(x), float(y), 0.0f);
    for (uint32_t y = 0; y < n; ++y) {
        for (uint32_t x = 0; x < n; ++x) {
            const uint32_t v = y * (n + 1) + x;
            triangles.emplace_back(v, v + 1, v + n + 2);
            triangles.emplace_back(v, v + n + 2, v + n + 1);
        }
    }
    return mesh_scene(std::move(positions), std::move(triangles));
}

inline Scene sample_scene(const char* name) {
    const std::filesystem::path file = std::filesystem::path(RT_SAMPLES_DIR) / name;
    if (!std::filesystem::exists(file))
        throw std::runtime_error(file.string() + " is missing: run `make samples` first");
    return load_scene(file);
}

// The box holding the middle 98% of the triangle centroids (and the spheres),
// so that a sample scene's large ground quad does not swamp its model.
inline Bounds3 central_bounds(const Scene& scene) {
    Bounds3 bounds;
    if (!scene.triangles.empty()) {
        for (int axis = 0; axis < 3; ++axis) {
            std::vector<float> centroids;
            for (const uvec3& t : scene.triangles)
                centroids.push_back((scene.positions[t[0]][axis] + scene.positions[t[1]][axis] + scene.positions[t[2]][axis]) / 3.0f);
            std::sort(centroids.begin(), centroids.end());
            bounds.min[axis] = centroids[centroids.size() / 100];
            bounds.max[axis] = centroids[centroids.size() - 1 - centroids.size() / 100];
        }
    }
    for (const Sphere& s : scene.spheres) bounds.extend(Bounds3{s.center - s.radius, s.center + s.radius});
    return bounds;
}

// Rays from random points in and around the scene's central bounds towards
// random points inside them or on random triangles; every third one ends at a
// random distance.
inline std::vector<Ray> random_rays(const Scene& scene, size_t count, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    const Bounds3 bounds = central_bounds(scene);
    const vec3 extent = bounds.extent();
    auto point = [&](float margin) {
        // The margin is as wide on every axis, so that rays also start off a flat scene's plane.
        const vec3 r(unit(rng), unit(rng), unit(rng));
        const vec3 size = extent + 2.0f * margin * max_component(extent);
        return bounds.center() + (r - 0.5f) * size;
    };
    auto point_on_triangle = [&] {
        const uvec3 t = scene.triangles[std::uniform_int_distribution<size_t>(0, scene.triangles.size() - 1)(rng)];
        float u = unit(rng), v = unit(rng);
        if (u + v > 1.0f) u = 1.0f - u, v = 1.0f - v;
        return (1.0f - u - v) * scene.positions[t[0]] + u * scene.positions[t[1]] + v * scene.positions[t[2]];
    };
    std::vector<Ray> rays;
    for (size_t i = 0; i < count; ++i) {
        const vec3 origin = point(0.5f);
        const vec3 target = i % 2 && !scene.triangles.empty() ? point_on_triangle() : point(0.0f);
        if (target == origin) continue;
        Ray ray{origin, glm::normalize(target - origin), kInfinity};
        if (i % 3 == 2) ray.t_max = unit(rng) * 2.0f * glm::length(extent);
        rays.push_back(ray);
    }
    return rays;
}

// A builder's input for a scene's triangles: each one's box and its centre.
struct BuildInput {
    std::vector<Bounds3> bounds;
    std::vector<vec3> centroids;
};

inline BuildInput build_input(const Scene& scene) {
    BuildInput input;
    for (const uvec3& t : scene.triangles) {
        Bounds3 b;
        for (int k = 0; k < 3; ++k) b.extend(scene.positions[t[k]]);
        input.bounds.push_back(b);
        input.centroids.push_back(b.center());
    }
    return input;
}

}  // namespace rt::testing
