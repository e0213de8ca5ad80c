#include "integrator/default_camera.h"

#include <cmath>

namespace rt {

Camera default_camera(const Scene& scene) {
    if (!scene.cameras.empty()) return scene.cameras.front().camera;
    const Bounds3 bounds = scene.bounds();
    const vec3 center = bounds.empty() ? vec3(0.0f) : bounds.center();
    const float radius = bounds.empty() ? 1.0f : glm::max(0.5f * glm::length(bounds.extent()), 1e-6f);
    const float fov_y = 45.0f;
    const float distance = radius / std::sin(0.5f * fov_y * kPi / 180.0f);
    const vec3 eye = center + distance * glm::normalize(vec3(0.0f, 0.25f, 1.0f));
    Camera camera;
    for (float v : {eye.x, eye.y, eye.z}) camera.add_position(v);
    for (float v : {center.x, center.y, center.z}) camera.add_target(v);
    for (float v : {0.0f, 1.0f, 0.0f}) camera.add_up(v);
    camera.set_fov_y(fov_y);
    return camera;
}

}  // namespace rt
