// What glTF's KHR_lights_punctual adds to a point light: a spot light's cone,
// the range window, and directional lights (suns), with the directions a sun
// of some angular diameter sends its shadow rays along.
#pragma once

#include <cmath>

#include "geometry/scene.h"
#include "integrator/sampling.h"
#include "util/math.h"

namespace rt {

// The specification's spot falloff (its sample implementation): 1 within the
// inner cone, 0 beyond the outer, and between them t^2 for t linear in the
// cosine of the angle from the axis. `wi`: unit, from the shaded point towards
// the light.
inline float spot_falloff(const Light& light, vec3 wi) {
    const float cos_angle = -glm::dot(light.direction, wi);
    const float scale = 1.0f / glm::max(0.001f, light.cos_inner - light.cos_outer);
    const float t = glm::clamp((cos_angle - light.cos_outer) * scale, 0.0f, 1.0f);
    return t * t;
}

// The specification's recommended window for `range`: clamp(1 - (d/range)^4,
// 0, 1)^2, which times 1/d^2 reaches 0 at d = range. 1 for range 0 (none).
inline float range_window(float range, float distance_squared) {
    if (range == 0.0f) return 1.0f;
    const float ratio_squared = distance_squared / (range * range);
    const float w = glm::clamp(1.0f - ratio_squared * ratio_squared, 0.0f, 1.0f);
    return w * w;
}

// What a point or spot light's 1/d^2 is scaled by beyond the plain point light.
inline float punctual_attenuation(const Light& light, vec3 wi, float distance_squared) {
    const float window = range_window(light.range, distance_squared);
    return light.kind == SPOT ? window * spot_falloff(light, wi) : window;
}

// Directions towards a sun of angular diameter > 0, uniform in the cone it
// subtends. Each carries the irradiance E = intensity (radiance times the
// cone's solid angle over the uniform density 1 / solid angle), so the
// estimate of the cosine-weighted light converges to what a surface sees.
class SunSampler {
  public:
    explicit SunSampler(const Light& light) {
        axis_ = -light.direction;
        orthonormal_basis(axis_, b1_, b2_);
        const float half = 0.5f * light.angular_diameter;
        const float s = std::sin(0.5f * half);
        one_minus_cos_max_ = 2.0f * s * s;  // 1 - cos(half), without cancellation
    }
    vec3 sample(vec2 u) const {
        // 1 - cos(theta) kept apart: a sun's cone is a fraction of a degree.
        const float one_minus_cos = u.x * one_minus_cos_max_;
        const float cos_theta = 1.0f - one_minus_cos;
        const float sin_theta = std::sqrt(one_minus_cos * (2.0f - one_minus_cos));
        const float phi = 2.0f * kPi * u.y;
        return glm::normalize(sin_theta * std::cos(phi) * b1_ + sin_theta * std::sin(phi) * b2_ + cos_theta * axis_);
    }

  private:
    vec3 axis_{0.0f}, b1_{0.0f}, b2_{0.0f};
    float one_minus_cos_max_ = 0.0f;
};

}  // namespace rt
