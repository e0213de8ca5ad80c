#include "integrator/sphere_light.h"

#include <cmath>

#include "integrator/sampling.h"

namespace rt {

SphereLightSampler::SphereLightSampler(const Light& light, LightSampling method, vec3 p)
    : light_(light), method_(method), p_(p), radiance_(sphere_light_radiance(light)) {
    if (method_ != CONE) return;
    const vec3 to_center = light.position - p;
    const float distance = length_any_scale(to_center);
    axis_ = to_center / distance;
    orthonormal_basis(axis_, b1_, b2_);
    sin_max_ = light.radius / distance;
    sin2_max_ = sin_max_ * sin_max_;
    // Below 1.5 degrees 1 - cos loses its digits: Taylor series instead.
    small_cone_ = sin2_max_ < 0.00068523f;
    one_minus_cos_max_ = small_cone_ ? 0.5f * sin2_max_ : 1.0f - std::sqrt(glm::max(0.0f, 1.0f - sin2_max_));
    cone_weight_ = radiance_ * (2.0f * kPi * one_minus_cos_max_);
}

bool SphereLightSampler::sample(vec2 u, SphereLightSample& sample) const {
    return method_ == SPHERE ? sample_area(u, sample) : sample_cone(u, sample);
}

// Uniform in the solid angle the sphere subtends (pbrt-v4, Sphere::Sample):
// the direction's angle theta from the axis is drawn as in a cone, then turned
// into the angle alpha at the centre, which gives the point on the near side
// without intersecting a ray that may graze the sphere.
bool SphereLightSampler::sample_cone(vec2 u, SphereLightSample& sample) const {
    float cos_theta, sin2_theta;
    if (small_cone_) {
        sin2_theta = sin2_max_ * u.x;
        cos_theta = std::sqrt(1.0f - sin2_theta);
    } else {
        cos_theta = 1.0f - u.x * one_minus_cos_max_;
        sin2_theta = 1.0f - cos_theta * cos_theta;
    }
    const float cos_alpha =
        sin2_theta / sin_max_ + cos_theta * std::sqrt(glm::max(0.0f, 1.0f - sin2_theta / sin2_max_));
    const float sin_alpha = std::sqrt(glm::max(0.0f, 1.0f - cos_alpha * cos_alpha));
    const float phi = 2.0f * kPi * u.y;
    const vec3 normal = -(sin_alpha * std::cos(phi) * b1_ + sin_alpha * std::sin(phi) * b2_ + cos_alpha * axis_);
    sample.point = light_.position + light_.radius * normal;
    sample.wi = normalize_any_scale(sample.point - p_);
    sample.weight = cone_weight_;
    return true;
}

// Uniform over the sphere's area, as the 2020 report chose its 200 points. The
// report then counted the unblocked points and scaled a point light by their share,
// which is biased twice: points on the far side counted as visible (the light
// does not block its own rays there), and every point weighed the same
// whatever its distance and the angle it is seen at. Weighting each point by
// cos(theta_light) / distance^2 over its density 1 / (4 pi r^2), and the far
// side by zero, makes the estimate converge to what CONE converges to.
bool SphereLightSampler::sample_area(vec2 u, SphereLightSample& sample) const {
    const float z = 1.0f - 2.0f * u.x;
    const float r = std::sqrt(glm::max(0.0f, 1.0f - z * z));
    const float phi = 2.0f * kPi * u.y;
    const vec3 normal(r * std::cos(phi), r * std::sin(phi), z);
    sample.point = light_.position + light_.radius * normal;
    const vec3 to_p = p_ - sample.point;
    const float distance = length_any_scale(to_p);
    const float cos_light = glm::dot(normal, to_p) / distance;
    if (!(cos_light > 0.0f)) return false;
    sample.wi = -to_p / distance;
    // r^2 / d^2 as a squared ratio: both squares leave float's range at scales the ratio does not.
    const float radius_over_distance = light_.radius / distance;
    sample.weight = radiance_ * (4.0f * kPi * cos_light * radius_over_distance * radius_over_distance);
    return true;
}

}  // namespace rt
