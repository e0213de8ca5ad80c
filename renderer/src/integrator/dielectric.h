// Smooth dielectric interfaces (pbrt-v4, "Specular Reflection and
// Transmission"): the unpolarized Fresnel reflectance and Snell's law. Both
// take the relative index eta = n_transmitted / n_incident for a direction on
// the side the normal points to, and handle the other side by inverting eta,
// so callers need only know which medium the normal points into.
#pragma once

#include <algorithm>
#include <cmath>

#include "util/math.h"

namespace rt {

// Fraction of light reflected at a smooth interface; cos_theta_i is the cosine
// between the incident direction (pointing away from the surface) and the
// normal. 1 past the critical angle: total internal reflection.
inline float fr_dielectric(float cos_theta_i, float eta) {
    cos_theta_i = std::clamp(cos_theta_i, -1.0f, 1.0f);
    // Negative cosine: the direction is on the far side, where eta is inverted.
    if (cos_theta_i < 0.0f) {
        eta = 1.0f / eta;
        cos_theta_i = -cos_theta_i;
    }
    const float sin2_theta_i = 1.0f - cos_theta_i * cos_theta_i;
    const float sin2_theta_t = sin2_theta_i / (eta * eta);
    if (sin2_theta_t >= 1.0f) return 1.0f;
    const float cos_theta_t = std::sqrt(std::max(0.0f, 1.0f - sin2_theta_t));
    const float r_parallel = (eta * cos_theta_i - cos_theta_t) / (eta * cos_theta_i + cos_theta_t);
    const float r_perpendicular = (cos_theta_i - eta * cos_theta_t) / (cos_theta_i + eta * cos_theta_t);
    return (r_parallel * r_parallel + r_perpendicular * r_perpendicular) / 2.0f;
}

// Snell's law. wi: unit direction pointing away from the surface on the side
// of n; wt: the unit transmitted direction, on the other side. False on total
// internal reflection.
inline bool refract(vec3 wi, vec3 n, float eta, vec3& wt) {
    float cos_theta_i = glm::dot(n, wi);
    if (cos_theta_i < 0.0f) {
        eta = 1.0f / eta;
        cos_theta_i = -cos_theta_i;
        n = -n;
    }
    const float sin2_theta_i = std::max(0.0f, 1.0f - cos_theta_i * cos_theta_i);
    const float sin2_theta_t = sin2_theta_i / (eta * eta);
    if (sin2_theta_t >= 1.0f) return false;
    const float cos_theta_t = std::sqrt(std::max(0.0f, 1.0f - sin2_theta_t));
    wt = -wi / eta + (cos_theta_i / eta - cos_theta_t) * n;
    return true;
}

}  // namespace rt
