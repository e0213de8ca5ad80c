#include "load/light_rig.h"

#include "integrator/default_camera.h"

namespace rt {
namespace {

vec3 vector_of(const google::protobuf::RepeatedField<float>& v, vec3 fallback) {
    return v.size() == 3 ? vec3(v[0], v[1], v[2]) : fallback;
}

}  // namespace

void add_light_rig(Scene& scene) {
    const Camera camera = default_camera(scene);
    const vec3 eye = vector_of(camera.position(), vec3(0.0f, 0.0f, 1.0f));
    const vec3 forward = try_normalize(vector_of(camera.target(), vec3(0.0f)) - eye).value_or(vec3(0.0f, 0.0f, -1.0f));
    const vec3 up_hint = vector_of(camera.up(), vec3(0.0f, 1.0f, 0.0f));
    const vec3 right = try_normalize(glm::cross(forward, up_hint)).value_or(vec3(1.0f, 0.0f, 0.0f));
    const vec3 up = glm::cross(right, forward);

    const Bounds3 bounds = scene.bounds();
    const vec3 center = bounds.empty() ? vec3(0.0f) : bounds.center();
    const float radius = bounds.empty() ? 1.0f : glm::max(0.5f * glm::length(bounds.extent()), 1e-6f);
    const auto add = [&](const char* name, vec3 towards_light, vec3 lux) {
        Light light;
        light.name = name;
        light.kind = DIRECTIONAL;
        light.direction = -glm::normalize(towards_light);
        light.position = center - 2.0f * radius * light.direction;
        light.intensity = lux;
        scene.lights.push_back(light);
        ++scene.rig_lights;
    };
    add("default rig: key", -0.6f * forward + 0.8f * up - 0.5f * right, vec3(kRigKeyLux));
    add("default rig: fill", -0.8f * forward + 0.2f * up + 0.7f * right, kRigFillLux * vec3(0.9f, 0.95f, 1.0f));
    scene.rig_background = scene.background.black() ? Background(kRigSky) : scene.background;
}

}  // namespace rt
