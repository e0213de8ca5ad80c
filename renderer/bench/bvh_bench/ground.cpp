#include "ground.h"

namespace rt::bench {
namespace {

Bounds3 triangle_box(const Scene& scene, const uvec3& t) {
    Bounds3 box;
    for (int k = 0; k < 3; ++k) box.extend(scene.positions[t[k]]);
    return box;
}

}  // namespace

std::optional<Scene> without_ground_quad(const Scene& scene) {
    const double scene_area = scene.bounds().surface_area();
    if (scene_area <= 0.0 || scene.moving()) return std::nullopt;
    std::vector<bool> ground(scene.triangles.size());
    size_t ground_count = 0;
    Bounds3 rest;
    for (size_t i = 0; i < scene.triangles.size(); ++i) {
        const Bounds3 box = triangle_box(scene, scene.triangles[i]);
        ground[i] = box.surface_area() >= 0.25 * scene_area;
        ground_count += ground[i];
        if (!ground[i]) rest.extend(box);
    }
    if (ground_count == 0 || ground_count > 2 || ground_count == scene.triangles.size() ||
        rest.surface_area() >= 0.1 * scene_area)
        return std::nullopt;
    // A copy, so that every per-triangle array the builders read stays aligned.
    Scene mesh = scene;
    mesh.triangles.clear();
    mesh.triangle_materials.clear();
    for (size_t i = 0; i < scene.triangles.size(); ++i) {
        if (ground[i]) continue;
        mesh.triangles.push_back(scene.triangles[i]);
        if (i < scene.triangle_materials.size()) mesh.triangle_materials.push_back(scene.triangle_materials[i]);
    }
    return mesh;
}

}  // namespace rt::bench
