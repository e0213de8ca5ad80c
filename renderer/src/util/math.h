// Vector types and the few numeric helpers every part of the renderer shares.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>

#include <glm/glm.hpp>

namespace rt {

using vec2 = glm::vec2;
using vec3 = glm::vec3;
using dvec3 = glm::dvec3;
using uvec3 = glm::uvec3;
using mat3 = glm::mat3;
using mat4 = glm::mat4;
using dmat4 = glm::dmat4;

inline constexpr float kInfinity = std::numeric_limits<float>::infinity();
inline constexpr float kPi = 3.14159265358979323846f;

// Bound on the relative rounding error of n chained float operations
// (pbrt-v4, "Floating-Point Arithmetic": gamma(n) = n u / (1 - n u)).
constexpr float gamma_bound(int n) {
    constexpr float u = std::numeric_limits<float>::epsilon() * 0.5f;
    return (n * u) / (1 - n * u);
}

// Rec. 709 luminance of linear RGB.
inline float luminance(vec3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

inline float max_component(vec3 v) { return glm::max(v.x, glm::max(v.y, v.z)); }
inline int max_dimension(vec3 v) { return v.x > v.y ? (v.x > v.z ? 0 : 2) : (v.y > v.z ? 1 : 2); }

// |v| and v / |v| for vectors of any magnitude. glm::length and
// glm::normalize square the components, which overflows above about 1e19 and
// underflows below about 1e-19; dividing by the largest one first keeps the
// squares near 1. normalize_any_scale(0) is NaN, as glm::normalize(0) is.
inline float length_any_scale(vec3 v) {
    const float largest = max_component(glm::abs(v));
    return largest > 0.0f ? largest * glm::length(v / largest) : 0.0f;
}
inline vec3 normalize_any_scale(vec3 v) { return glm::normalize(v / max_component(glm::abs(v))); }

inline bool is_finite(vec3 v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// v / |v|, or nothing when |v| is zero or not finite (a component is infinite
// or NaN, or the squares overflow): for any glm vector or quaternion, whose
// callers each say what takes the place of a direction that cannot be had.
template <class V>
std::optional<V> try_normalize(const V& v) {
    using glm::length;  // found for quaternions too, by argument
    const auto l = length(v);
    if (!(l > 0) || !std::isfinite(l)) return std::nullopt;
    return v / l;
}

}  // namespace rt
