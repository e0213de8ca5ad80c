// glTF normal maps: the shading normal bent by a tangent-space normal
// texture, in the frame of the vertex normal and the vertex tangents (the
// file's TANGENT, or MikkTSpace's where it has none: load/generate_tangents.h).
#pragma once

#include "geometry/material.h"
#include "geometry/scene.h"
#include "geometry/surface.h"
#include "util/ray.h"

namespace rt {

// glTF's tangent-space normal: n' = normalize(T x + B y + N z), where (x, y,
// z) = 2 texel - 1 with x and y times `scale`, T is `tangent` made
// orthogonal to the unit normal N (Gram-Schmidt) and B = w cross(N, T) with
// w the tangent's sign. N itself where the frame or the result degenerates.
vec3 bend_normal(vec3 n, glm::vec4 tangent, vec3 texel, float scale);

// The tangent at the hit: the vertex tangents interpolated, w the sign of
// the interpolated w. (0, 0, 0, 0) where a vertex has none or the hit is not
// on a triangle.
glm::vec4 tangent_at(const Scene& scene, const Hit& hit, float time);

// Bends s.ns, which face_viewer has oriented, by `m`'s normal texture (call
// it only when there is one). `authored` is the interpolated normal as
// surface_at gave it, the frame the map was baked in; the bent normal turns
// with the same flip face_viewer gave the normals. A bent normal that faces
// away from the viewer (`wo`) is tilted back until it just faces it, as
// Cycles and three.js keep normal-mapped shading on the visible side.
void apply_normal_map(const Scene& scene, const Material& m, const Hit& hit, vec3 authored, vec3 wo,
                      SurfaceHit& s);

}  // namespace rt
