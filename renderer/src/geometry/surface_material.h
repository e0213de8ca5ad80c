// A material as shading sees it at one hit: its textures and the vertex
// colours applied, and glTF's metallic-roughness inputs turned into the Phong
// terms texel by texel, through the same mapping the loader uses for the
// factors (docs/materials.md). A material without textures or vertex colours
// gives exactly its stored terms, so untextured scenes shade as they always did.
#pragma once

#include "geometry/material.h"
#include "geometry/scene.h"
#include "geometry/surface.h"

namespace rt {

struct SurfaceMaterial {
    vec3 diffuse{0.0f};
    vec3 specular{0.0f};
    float shininess = 1.0f;
    vec3 reflectance{0.0f};
    vec3 emission{0.0f};    // linear radiance the surface adds, seen by every ray
    float coverage = 1.0f;  // how much of the light the surface stops: MASK 0 or 1, BLEND alpha
    float occlusion = 1.0f; // scales the default rig's fill light only
};

SurfaceMaterial surface_material(const Scene& scene, const Material& m, const SurfaceHit& s);

// The coverage alone, for rays that only need to know whether (and how much)
// a surface is there: shadow rays and the traversal's hit filter.
float surface_coverage(const Scene& scene, const Material& m, const SurfaceHit& s);

// The coverage of `triangle` at barycentrics (u, v), for a traversal that has
// not built the SurfaceHit yet. 1 for an opaque material.
float triangle_coverage(const Scene& scene, uint32_t triangle, float u, float v);

}  // namespace rt
