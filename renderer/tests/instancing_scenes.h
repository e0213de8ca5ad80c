// Scenes with instances built in code, and the same scenes flattened into
// world-space triangles, for the instancing tests.
#pragma once

#include <random>

#include <glm/gtc/matrix_transform.hpp>

#include "geometry/scene.h"
#include "stability_scenes.h"

namespace rt::testing {

// Appends `mesh` (in its own space) as a shared mesh of `scene`, after any
// earlier ones; returns its number.
inline uint32_t add_shared_mesh(Scene& scene, const Scene& mesh, uint32_t material) {
    SharedMesh shared{uint32_t(scene.triangles.size()), uint32_t(mesh.triangles.size())};
    append_mesh(scene, mesh, vec3(0.0f), 1.0f, material);
    scene.meshes.push_back(shared);
    return uint32_t(scene.meshes.size() - 1);
}

// translate * rotate * scale, the rotation about `axis` by `angle` radians.
inline Affine placement(vec3 translation, vec3 axis, float angle, vec3 scale) {
    const glm::mat4 m = glm::scale(glm::rotate(glm::translate(glm::mat4(1.0f), translation), angle, axis), scale);
    return {glm::mat3(m), vec3(m[3])};
}

inline Affine random_placement(std::mt19937& rng, float spread, bool mirrored) {
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    std::uniform_real_distribution<float> size(0.4f, 2.5f);
    const vec3 axis = glm::normalize(vec3(unit(rng), unit(rng), unit(rng)) + vec3(0.0f, 0.0f, 1e-3f));
    vec3 scale(size(rng), size(rng), size(rng));
    if (mirrored) scale.x = -scale.x;
    return placement(spread * vec3(unit(rng), unit(rng), unit(rng)), axis, 3.14159265f * unit(rng), scale);
}

// The same scene with every instance's triangles copied into world space
// (and the shared meshes dropped), normals through the normal matrix; in a
// moving scene each copied vertex at close is where the instance then puts it.
inline Scene flattened(const Scene& scene) {
    Scene flat = scene;
    flat.meshes.clear();
    flat.instances.clear();
    flat.triangles.resize(scene.world_triangles());
    flat.triangle_materials.resize(scene.world_triangles());
    for (const Instance& instance : scene.instances) {
        const SharedMesh& mesh = scene.meshes[instance.mesh];
        for (uint32_t t = mesh.first_triangle; t < mesh.first_triangle + mesh.triangle_count; ++t) {
            uvec3 corners;
            for (int k = 0; k < 3; ++k) {
                const uint32_t v = scene.triangles[t][k];
                corners[k] = uint32_t(flat.positions.size());
                flat.positions.push_back(instance.to_world.point(scene.positions[v]));
                flat.normals.push_back(glm::normalize(instance.normal_to_world() * scene.normals[v]));
                if (scene.moving()) {
                    const Instance close = Instance::make(instance.mesh, instance.to_world_close);
                    flat.positions_close.push_back(close.to_world.point(scene.positions_close[v]));
                    flat.normals_close.push_back(glm::normalize(close.normal_to_world() * scene.normals_close[v]));
                }
                if (!scene.texcoords.empty()) flat.texcoords.push_back(scene.texcoords[v]);
            }
            flat.triangles.push_back(corners);
            flat.triangle_materials.push_back(scene.triangle_materials[t]);
        }
    }
    return flat;
}

// A random soup in world space and `count` instances of two shared meshes (an
// icosphere and a torus), placed at random, every fifth one mirrored.
inline Scene instanced_soup(uint32_t count, uint32_t seed) {
    Scene scene = random_soup(300, seed);
    const uint32_t material = 0;
    const uint32_t sphere = add_shared_mesh(scene, with_radial_normals(icosphere(2)), material);
    const uint32_t ring = add_shared_mesh(scene, torus(24, 12, 1.0f, 0.35f), material);
    std::mt19937 rng(seed);
    for (uint32_t i = 0; i < count; ++i)
        scene.instances.push_back(Instance::make(i % 2 ? ring : sphere, random_placement(rng, 9.0f, i % 5 == 4)));
    return scene;
}

// instanced_soup whose instances move while the shutter is open (each
// third one stands still): shifted by up to `shift`, turned a little more and
// scaled; the world-space soup stands still, so only the top level moves.
inline Scene moving_instanced_soup(uint32_t count, uint32_t seed, float shift) {
    Scene scene = instanced_soup(count, seed);
    scene.positions_close = scene.positions;
    scene.normals_close = scene.normals;
    std::mt19937 rng(seed + 1);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    for (uint32_t i = 0; i < scene.instances.size(); ++i) {
        if (i % 3 == 2) continue;
        const Instance& open = scene.instances[i];
        const glm::mat3 turn = glm::mat3(glm::rotate(glm::mat4(1.0f), 0.4f * unit(rng), vec3(0.0f, 1.0f, 0.0f)));
        const Affine close{turn * open.to_world.linear * (1.0f + 0.2f * unit(rng)),
                           open.to_world.translation + shift * vec3(unit(rng), unit(rng), unit(rng))};
        scene.instances[i] = Instance::make(open.mesh, open.to_world, close);
    }
    return scene;
}

}  // namespace rt::testing
