// Analytic spheres. Few per scene, so they are solved in double precision: the
// roots then carry far less error than the spawn offset of a float hit point,
// and a ray leaving a sphere never re-hits it at t ~ 0.
#pragma once

#include <cmath>
#include <initializer_list>

#include "util/math.h"
#include "util/ray.h"

namespace rt {

struct Sphere {
    vec3 center{0.0f};
    float radius = 1.0f;
    uint32_t material = 0;
};

// Nearest root with 0 < t < ray.t_max. Uses the numerically stable form of the
// quadratic (Ray Tracing Gems, ch. 7): no cancellation for small or distant spheres.
inline bool intersect_sphere(const Ray& ray, const Sphere& s, float& t_hit) {
    const dvec3 d = glm::normalize(dvec3(ray.direction));
    const dvec3 f = dvec3(ray.origin) - dvec3(s.center);
    const double r = s.radius;
    const double b = glm::dot(f, d);
    const dvec3 l = f - b * d;
    const double discriminant = r * r - glm::dot(l, l);
    if (discriminant < 0.0) return false;
    const double c = glm::dot(f, f) - r * r;
    const double q = -b - std::copysign(std::sqrt(discriminant), b);
    double t0 = q != 0.0 ? c / q : 0.0;
    double t1 = q;
    if (t0 > t1) std::swap(t0, t1);
    // Direction may not be unit length in float; t is measured in its units.
    const double scale = 1.0 / glm::length(dvec3(ray.direction));
    for (double t : {t0 * scale, t1 * scale}) {
        if (t > 0.0 && t < double(ray.t_max)) {
            t_hit = float(t);
            if (t_hit > 0.0f) return true;
        }
    }
    return false;
}

// The hit point projected back onto the sphere, its error bound (pbrt-v4) and
// the outward normal there. The normal comes from the double-precision
// direction, not from the float point minus the centre, which squares to zero
// for radii below 1e-19 and vanishes for a sphere too small for floats to
// tell from its centre.
inline vec3 sphere_point(const Sphere& s, const Ray& ray, float t, vec3& p_error, vec3& normal) {
    const dvec3 c(s.center);
    const dvec3 n = glm::normalize(dvec3(ray.origin) + double(t) * dvec3(ray.direction) - c);
    const vec3 pf(c + double(s.radius) * n);
    p_error = gamma_bound(5) * glm::abs(pf);
    normal = vec3(n);
    return pf;
}

}  // namespace rt
