// Where shadow rays leave a smooth-shaded triangle. A low-poly mesh with
// interpolated normals is lit as if it were round, but its shadow rays start
// on the flat facets: near the terminator they hit the neighbouring facets
// and the lit side shows black, facet-shaped patches. Hanika's fix ("Hacking
// the Shadow Terminator", Ray Tracing Gems II, 2021, ch. 4) starts them from
// the point the vertex normals describe instead: the hit point moved out of
// each vertex's tangent plane it lies below, blended by the barycentrics,
//   p' = p - sum_i b_i min(0, (p - p_i) . n_i) n_i,
// which lifts points on a convex part of the surface and leaves flat and
// concave parts (where no self-shadowing error arises) where they are.
#pragma once

#include "geometry/scene.h"
#include "geometry/surface.h"
#include "util/ray.h"

namespace rt {

// The shadow rays' start for the hit: p' with its error bound, the normals
// taken on the side `side` (+1: the side they point to, -1: the other one, as
// when the viewer looks at the back). Spheres and flat-shaded triangles give
// the hit point itself. `corners`: the triangle's, as surface_at found them
// (else found again).
struct ShadowOrigin {
    vec3 p;
    vec3 p_error;
};
ShadowOrigin shadow_terminator_origin(const Scene& scene, const Hit& hit, const SurfaceHit& s, float side,
                                      const TriangleCorners* corners = nullptr);

}  // namespace rt
