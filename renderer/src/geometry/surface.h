// What shading needs at a hit: the point with its rounding-error bound (for
// spawning rays), geometric and shading normals, texture coordinates, material.
#pragma once

#include "util/ray.h"
#include "geometry/scene.h"
#include "geometry/triangle_corners.h"

namespace rt {

struct SurfaceHit {
    vec3 p{0.0f};
    vec3 p_error{0.0f};  // bound on |p - exact point| per axis
    vec3 ng{0.0f};       // geometric normal, unit length
    vec3 ns{0.0f};       // shading normal, unit length: interpolated, then bent by a normal map
    // The interpolated normal, never bent: the smooth surface the vertex
    // normals describe, which a light must be above to light the point.
    vec3 n_smooth{0.0f};
    vec2 uv{0.0f};       // TEXCOORD_0
    vec2 uv1{0.0f};      // TEXCOORD_1
    glm::vec4 color{1.0f};  // COLOR_0, white without
    uint32_t material = 0;
    float time = 0.0f;   // the shutter time of the ray that hit, for the rays spawned here
    // The ray cone (integrator/ray_cone.h) of the ray that hit, which the
    // integrator fills in and texture lookups filter by: zero width reads
    // level 0. The area ratios are the triangle's, for its level of detail.
    float cone_width = 0.0f;      // the cone's width at p
    float cone_spread = 0.0f;     // its spread angle, kept by the rays spawned here
    float cos_incidence = 1.0f;   // |cos| between the ray and ng: the footprint stretches by its inverse
    float uv_area_ratio = 0.0f;   // |Δuv| / |Δworld| of the triangle for TEXCOORD_0 (uv area per world area)
    float uv1_area_ratio = 0.0f;  // the same for TEXCOORD_1
};

// The point is interpolated from the triangle's vertices with the barycentrics
// rather than taken as origin + t * direction: its error then depends only on
// the vertices' magnitude, not on how far the ray travelled. In a moving scene
// the vertices and normals are those at ray.time. `corners`, when given, gets
// the triangle's corners as found (a triangle hit only), for
// shadow_terminator_origin: an instance's take a transform to make.
SurfaceHit surface_at(const Scene& scene, const Ray& ray, const Hit& hit, TriangleCorners* corners = nullptr);

// Orients both normals towards the side the ray came from (the 2020 report's
// section 2.1), flipping them together so they stay consistent; a shading
// normal that still faces away (interpolation at a silhouette) falls back to
// the geometric one. n_smooth is set to the (oriented) shading normal.
void face_viewer(SurfaceHit& s, vec3 towards_viewer);

}  // namespace rt
