// A hit triangle's corners as shading sees them: in world space and at the
// ray's shutter time, whether the triangle is the scene's own or an
// instance's (geometry/instance.h).
#pragma once

#include "geometry/scene.h"
#include "util/ray.h"

namespace rt {

struct TriangleCorners {
    uvec3 vertices;
    vec3 p[3];
    // The vertex normals, interpolated over the shutter but not renormalised,
    // except an instance's, which the transform leaves unit length.
    vec3 n[3];
    // What placing an instance's triangle in the world adds to the rounding
    // bound of a point on it: the transform's rounding, and that of the way
    // back, which a ray spawned there takes into the mesh's space. Zero for
    // a world-space triangle.
    vec3 placement_error{0.0f};
};

// Only for a triangle hit (hit.primitive < scene.triangles.size()).
TriangleCorners triangle_corners(const Scene& scene, const Hit& hit, float time);

}  // namespace rt
