#include "geometry/shadow_terminator.h"

#include <algorithm>

#include "geometry/triangle_corners.h"

namespace rt {

ShadowOrigin shadow_terminator_origin(const Scene& scene, const Hit& hit, const SurfaceHit& s, float side,
                                      const TriangleCorners* corners) {
    if (hit.primitive >= scene.triangles.size()) return {s.p, s.p_error};
    const TriangleCorners c = corners ? *corners : triangle_corners(scene, hit, s.time);
    const float b[3] = {1.0f - hit.u - hit.v, hit.u, hit.v};
    vec3 offset(0.0f);
    for (int i = 0; i < 3; ++i) {
        // Unit at both ends of the shutter, in between a little shorter (as
        // surface_at interpolates them), which lowers the lift by as much.
        const vec3 p = c.p[i];
        const vec3 n = side * c.n[i];
        offset -= b[i] * std::min(0.0f, glm::dot(s.p - p, n)) * n;
    }
    // The lift is computed from differences of nearby points; its own
    // rounding is bounded like the point's (surface.cpp) plus its size.
    return {s.p + offset, s.p_error + gamma_bound(7) * glm::abs(offset)};
}

}  // namespace rt
