#include "integrator/camera.h"

#include <cmath>
#include <stdexcept>

namespace rt {
namespace {

vec3 to_vec3(const google::protobuf::RepeatedField<float>& v, vec3 fallback) {
    return v.size() == 3 ? vec3(v[0], v[1], v[2]) : fallback;
}

// Poses that pass the checks at both ends can still degenerate in between
// (position passing through target, up turning through the view direction):
// the pose is checked at this many equal steps of the shutter interval too.
constexpr int kPoseChecks = 64;

}  // namespace

ViewCamera::ViewCamera(const Camera& camera, uint32_t width, uint32_t height)
    : inv_width_(1.0f / float(width)), inv_height_(1.0f / float(height)) {
    const vec3 y_up(0.0f, 1.0f, 0.0f);
    const vec3 ahead(0.0f, 0.0f, -1.0f);  // a target for a pose without one
    open_ = {to_vec3(camera.position(), vec3(0.0f)), to_vec3(camera.target(), ahead), to_vec3(camera.up(), y_up)};
    check(open_, "camera");
    orthographic_ = camera.projection() == ORTHOGRAPHIC;
    if (orthographic_) {
        // No default: a height that suits one scene is nonsense in another.
        if (!camera.has_ortho_height())
            throw std::invalid_argument("camera.ortho_height: is required for an ORTHOGRAPHIC camera");
        half_y_ = 0.5f * camera.ortho_height();
    } else {
        const float fov_y = camera.has_fov_y() ? camera.fov_y() : 45.0f;
        half_y_ = std::tan(0.5f * fov_y * kPi / 180.0f);
    }
    half_x_ = half_y_ * (float(width) / float(height));
    still_ = frame(open_);
    if (!camera.has_shutter_close()) return;

    const CameraPose& end = camera.shutter_close();
    close_ = {to_vec3(end.position(), vec3(0.0f)), to_vec3(end.target(), ahead), to_vec3(end.up(), y_up)};
    check(close_, "camera.shutter_close");
    moving_ = close_.position != open_.position || close_.target != open_.target || close_.up != open_.up;
    for (int i = 1; moving_ && i < kPoseChecks; ++i) {
        const float time = float(i) / float(kPoseChecks);
        check(pose_at(time), "camera.shutter_close",
              " (between the poses, at shutter time " + std::to_string(time) + ")");
    }
}

void ViewCamera::check(const Pose& pose, const std::string& what, const std::string& when) {
    const vec3 view = pose.target - pose.position;
    if (view == vec3(0.0f) || !is_finite(view))
        throw std::invalid_argument(what + ": position and target must differ" + when);
    // A zero or infinite up normalizes to NaN, which fails the test too.
    const vec3 side = glm::cross(normalize_any_scale(view), normalize_any_scale(pose.up));
    if (!(glm::length(side) > 1e-6f))
        throw std::invalid_argument(what + ".up: must not be parallel to the view direction" + when);
}

ViewCamera::Pose ViewCamera::pose_at(float time) const {
    return {open_.position + time * (close_.position - open_.position),
            open_.target + time * (close_.target - open_.target), open_.up + time * (close_.up - open_.up)};
}

ViewCamera::Frame ViewCamera::frame(const Pose& pose) const {
    // Scenes span 1e-30 to 1e30: so may the distance to the target and the up vector.
    const vec3 forward = normalize_any_scale(pose.target - pose.position);
    const vec3 side = glm::cross(forward, normalize_any_scale(pose.up));
    return {pose.position, forward, glm::normalize(side) * half_x_, glm::normalize(glm::cross(side, forward)) * half_y_};
}

Ray ViewCamera::ray_through(const Frame& f, float px, float py, float time) const {
    const float sx = 2.0f * px * inv_width_ - 1.0f;
    const float sy = 1.0f - 2.0f * py * inv_height_;
    if (orthographic_) return Ray{f.position + sx * f.right + sy * f.up, f.forward, kInfinity, time};
    return Ray{f.position, glm::normalize(f.forward + sx * f.right + sy * f.up), kInfinity, time};
}

RayCone ViewCamera::ray_cone() const {
    const float height = 1.0f / inv_height_;
    return orthographic_ ? RayCone::parallel(2.0f * half_y_ / height) : RayCone::camera(half_y_, height);
}

Ray ViewCamera::generate_ray(float px, float py, float time) const {
    if (!moving_) return ray_through(still_, px, py, time);
    return ray_through(frame(pose_at(time)), px, py, time);
}

}  // namespace rt
