// Watertight ray/triangle intersection: Woop, Benthin and Wald, "Watertight
// Ray/Triangle Intersection", JCGT 2(1), 2013.
//
// The ray is sheared so that it runs along +z through the origin; the test then
// evaluates three 2D edge functions. A shared edge gives the two triangles the
// same edge function with opposite sign, bit for bit, so a ray through an edge or
// vertex hits at least one of the triangles sharing it: nothing leaks. This only
// holds without fused multiply-add contraction, hence -ffp-contract=off.
#pragma once

#include <cmath>

#include "util/math.h"
#include "util/ray.h"

namespace rt {

// Per-ray constants of the shear, computed once per ray.
struct WatertightRay {
    vec3 origin;
    int kx, ky, kz;   // axis permutation: kz is the direction's largest axis
    float sx, sy, sz; // shear coefficients

    WatertightRay() = default;
    explicit WatertightRay(const Ray& ray) : origin(ray.origin) {
        const vec3 d = ray.direction;
        kz = max_dimension(glm::abs(d));
        kx = (kz + 1) % 3;
        ky = (kx + 1) % 3;
        // Keep the winding of the edge functions independent of the ray's sign.
        if (d[kz] < 0.0f) std::swap(kx, ky);
        sx = d[kx] / d[kz];
        sy = d[ky] / d[kz];
        sz = 1.0f / d[kz];
    }
};

struct TriangleHit {
    float t;
    float u;  // weight of the second vertex
    float v;  // weight of the third vertex
};

// Finds a hit with 0 < t < t_max; a ray that starts exactly on the triangle
// (t == 0) does not hit it.
inline bool intersect_triangle(const WatertightRay& r, vec3 p0, vec3 p1, vec3 p2, float t_max,
                               TriangleHit& hit) {
    const vec3 a = p0 - r.origin;
    const vec3 b = p1 - r.origin;
    const vec3 c = p2 - r.origin;

    const float ax = a[r.kx] - r.sx * a[r.kz];
    const float ay = a[r.ky] - r.sy * a[r.kz];
    const float bx = b[r.kx] - r.sx * b[r.kz];
    const float by = b[r.ky] - r.sy * b[r.kz];
    const float cx = c[r.kx] - r.sx * c[r.kz];
    const float cy = c[r.ky] - r.sy * c[r.kz];

    float e0 = cx * by - cy * bx;  // weight of p0
    float e1 = ax * cy - ay * cx;  // weight of p1
    float e2 = bx * ay - by * ax;  // weight of p2

    // An edge function of exactly zero may be a rounding artefact; decide it in
    // double precision, where the products of floats are exact.
    if (e0 == 0.0f || e1 == 0.0f || e2 == 0.0f) {
        e0 = float(double(cx) * double(by) - double(cy) * double(bx));
        e1 = float(double(ax) * double(cy) - double(ay) * double(cx));
        e2 = float(double(bx) * double(ay) - double(by) * double(ax));
    }

    if ((e0 < 0.0f || e1 < 0.0f || e2 < 0.0f) && (e0 > 0.0f || e1 > 0.0f || e2 > 0.0f))
        return false;
    const float det = e0 + e1 + e2;
    if (det == 0.0f) return false;  // ray parallel to the triangle, or a degenerate one

    const float az = r.sz * a[r.kz];
    const float bz = r.sz * b[r.kz];
    const float cz = r.sz * c[r.kz];
    const float t_scaled = e0 * az + e1 * bz + e2 * cz;

    // 0 < t_scaled / det < t_max without dividing: compare with det's sign folded in.
    if (det < 0.0f ? (t_scaled >= 0.0f || t_scaled < t_max * det)
                   : (t_scaled <= 0.0f || t_scaled > t_max * det))
        return false;

    const float inv_det = 1.0f / det;
    const float t = t_scaled * inv_det;
    if (!(t < t_max)) return false;  // rounding of the division

    // A ray spawned just off this very triangle may still compute a tiny positive
    // t from rounding alone. Reject t inside its conservative error bound
    // (pbrt-v4, section 6.8.6): no fixed epsilon, it scales with the coordinates.
    const float max_zt = max_component(glm::abs(vec3(az, bz, cz)));
    const float max_xt = max_component(glm::abs(vec3(ax, bx, cx)));
    const float max_yt = max_component(glm::abs(vec3(ay, by, cy)));
    const float delta_z = gamma_bound(3) * max_zt;
    const float delta_x = gamma_bound(5) * (max_xt + max_zt);
    const float delta_y = gamma_bound(5) * (max_yt + max_zt);
    const float delta_e = 2.0f * (gamma_bound(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
    const float max_e = max_component(glm::abs(vec3(e0, e1, e2)));
    const float delta_t = 3.0f * (gamma_bound(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) *
                          std::abs(inv_det);
    if (t <= delta_t) return false;

    hit = {t, e1 * inv_det, e2 * inv_det};
    return true;
}

inline bool intersect_triangle(const Ray& ray, vec3 p0, vec3 p1, vec3 p2, TriangleHit& hit) {
    return intersect_triangle(WatertightRay(ray), p0, p1, p2, ray.t_max, hit);
}

// Normal to the triangle, twice its area long. Formed in double, where products
// of float coordinates can neither overflow nor underflow: it is zero only for
// a triangle with no area at all, at any scale (in float it vanishes for edges
// below 1e-19 and overflows above 1e19).
inline dvec3 area_normal(vec3 p0, vec3 p1, vec3 p2) {
    return glm::cross(dvec3(p1) - dvec3(p0), dvec3(p2) - dvec3(p0));
}

// Twice the area; zero for triangles that no ray can hit.
inline double doubled_area(vec3 p0, vec3 p1, vec3 p2) { return glm::length(area_normal(p0, p1, p2)); }

}  // namespace rt
