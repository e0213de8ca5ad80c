#include "camera.h"

#include <cmath>
#include <stdexcept>

namespace rt {
namespace {

vec3 to_vec3(const google::protobuf::RepeatedField<float>& v, vec3 fallback) {
    return v.size() == 3 ? vec3(v[0], v[1], v[2]) : fallback;
}

}  // namespace

PinholeCamera::PinholeCamera(const Camera& camera, uint32_t width, uint32_t height)
    : inv_width_(1.0f / float(width)), inv_height_(1.0f / float(height)) {
    position_ = to_vec3(camera.position(), vec3(0.0f));
    const vec3 target = to_vec3(camera.target(), vec3(0.0f, 0.0f, -1.0f));
    const vec3 up = to_vec3(camera.up(), vec3(0.0f, 1.0f, 0.0f));
    const vec3 view = target - position_;
    if (!(glm::length(view) > 0.0f) || !is_finite(view))
        throw std::invalid_argument("camera: position and target must differ");
    forward_ = glm::normalize(view);
    const vec3 side = glm::cross(forward_, up);
    if (!(glm::length(side) > 1e-6f * glm::length(up)))
        throw std::invalid_argument("camera.up: must not be parallel to the view direction");
    const float fov_y = camera.has_fov_y() ? camera.fov_y() : 45.0f;
    const float tan_y = std::tan(0.5f * fov_y * kPi / 180.0f);
    const float aspect = float(width) / float(height);
    right_ = glm::normalize(side) * (tan_y * aspect);
    up_ = glm::normalize(glm::cross(side, forward_)) * tan_y;
}

Ray PinholeCamera::generate_ray(float px, float py) const {
    const float sx = 2.0f * px * inv_width_ - 1.0f;
    const float sy = 1.0f - 2.0f * py * inv_height_;
    return Ray{position_, glm::normalize(forward_ + sx * right_ + sy * up_), kInfinity};
}

}  // namespace rt
