// A loaded scene written back as one binary glTF 2.0 file (GLB), so that the web
// viewer shows exactly what the renderer sees, whatever format the scene came
// in: world-space triangles after every repair the loader made, the materials
// as shaded, the analytic spheres, the lights and the cameras.
#pragma once

#include <string>

#include "geometry/scene.h"

namespace rt {

// The GLB's bytes. What it holds:
// - one mesh on one untransformed node (positions are already in world space),
//   one primitive per material with POSITION (with min and max), NORMAL,
//   TEXCOORD_0 when the scene has texture coordinates, and uint32 indices;
// - the materials in the scene's order as pbrMetallicRoughness: baseColorFactor
//   is the diffuse colour (linear, clamped to glTF's [0, 1]), metallic 0, the
//   roughness whose lobe matches the Phong exponent (docs/materials.md's mapping
//   inverted), the diffuse texture embedded as an sRGB PNG; the exact Phong terms
//   in `extras.rt.phong` (the JSON form of rt.PhongMaterial);
// - each analytic sphere as a UV-sphere mesh on its own node, placed by the
//   node's translation and scale, with `extras.rt.sphere` {center, radius};
// - the lights as KHR_lights_punctual point lights on nodes at their positions,
//   spherical ones with `extras.rt.radius`;
// - the cameras as perspective cameras (yfov in radians) on nodes looking at
//   their targets;
// - the background as the scene's `extras.rt`: `background` (a solid colour)
//   or `background_gradient` {bottom, horizon, top}, as rt.SceneExtras has
//   them; with the default rig, what misses see under it (its sky unless the
//   scene gives a background) likewise in `extras.rt_default_rig`.
// Loaded back, it gives the same triangles, diffuse colours, shininess,
// textures, background, light positions and intensities, and camera views; the
// loader does not read node extras, so spheres come back as their meshes and
// spherical lights as point lights.
//
// Throws std::length_error when the scene does not fit in a GLB (4 GiB), and
// std::invalid_argument when a triangle names a material the scene lacks.
std::string export_glb(const Scene& scene);

}  // namespace rt
