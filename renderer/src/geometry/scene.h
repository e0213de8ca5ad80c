// A scene as the renderer sees it: world-space triangles with per-vertex
// attributes, analytic spheres, Phong materials, lights and cameras. The loaders
// (loader.h) build one from glTF or OBJ; nothing here knows about file formats.
//
// Triangle vertices may move while the shutter is open: each travels in a
// straight line from its place at shutter open (time 0) to its place at
// shutter close (time 1). Spheres, lights and materials stand still.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "util/bounds.h"
#include "geometry/background.h"
#include "geometry/instance.h"
#include "geometry/material.h"
#include "util/math.h"
#include "util/ray.h"
#include "rt/render.pb.h"
#include "rt/scene.pb.h"
#include "geometry/sphere.h"

namespace rt {

// A point light (radius 0), a spherical light, a spot light or a directional
// one (`kind`, the schema's LightKind). `intensity` is colour times candela:
// irradiance at distance d is intensity / d^2, which a spherical light keeps by
// emitting the radiance intensity / (pi r^2) (sphere_light.h); for a
// directional light it is colour times lux, the irradiance it gives a surface
// facing it.
struct Light {
    std::string name;
    vec3 position{0.0f};
    vec3 intensity{1.0f};
    float radius = 0.0f;
    LightKind kind = POINT;
    vec3 direction{0.0f, 0.0f, -1.0f};  // spot, directional: unit, the way the light travels
    float cos_inner = 1.0f;             // spot: cosines of the cone angles
    float cos_outer = 0.0f;
    float range = 0.0f;                 // point, spot: 0 for no limit
    float angular_diameter = 0.0f;      // directional: radians, 0 for hard shadows

    // A point light as the 2020 report had them: no cone, no range, no radius.
    bool plain_point() const { return kind == POINT && radius == 0.0f && range == 0.0f; }
};

struct SceneCamera {
    std::string name;
    Camera camera;  // the proto message: position, target, up, fov_y
};

// Where a point moving in a straight line is at shutter time `time`: exactly
// `open` at time 0 and for a point that does not move. Intersection and
// shading both interpolate with it, so they agree on where a triangle is.
inline vec3 lerp_position(vec3 open, vec3 close, float time) { return open + time * (close - open); }

struct Scene {
    // Vertex attributes, all indexed by the same vertex index. `texcoords` is
    // empty when no mesh has any; `normals` always has one per vertex.
    std::vector<vec3> positions;
    std::vector<vec3> normals;
    std::vector<vec2> texcoords;
    // TEXCOORD_1, COLOR_0 (linear RGBA) and TANGENT (xyz, w the bitangent's
    // sign), each empty when no mesh has it; a mesh without it gets (0, 0),
    // (1, 1, 1, 1) and (0, 0, 0, 0) when another has it. Tangents are those
    // at shutter open, also in a moving scene.
    std::vector<vec2> texcoords1;
    std::vector<glm::vec4> colors;
    std::vector<glm::vec4> tangents;
    // The positions and normals at shutter close, one per vertex when anything
    // moves, else empty. Normals are interpolated like positions, then
    // renormalised.
    std::vector<vec3> positions_close;
    std::vector<vec3> normals_close;

    std::vector<uvec3> triangles;            // vertex indices
    std::vector<uint32_t> triangle_materials; // one per triangle
    // Meshes drawn more than once, each stored once in its own space: their
    // triangles are the tail of `triangles`, from world_triangles() on, in
    // the order of `meshes`; the instances place them. Triangles before that
    // are in world space. In a moving scene an instanced mesh's vertices
    // have positions_close too (equal to positions: instances stand still).
    std::vector<SharedMesh> meshes;
    std::vector<Instance> instances;
    // One per instance where the loader knows it (else empty): the name of
    // the node that placed it, or nodes[i], for the debugger.
    std::vector<std::string> instance_names;

    std::vector<Sphere> spheres;
    std::vector<Material> materials;
    std::vector<Texture> textures;
    std::vector<Light> lights;
    std::vector<SceneCamera> cameras;
    Background background;  // black unless the scene gives one
    // With no lights of its own, the loader gives the scene a default rig
    // (load/light_rig.h): the last `rig_lights` lights, and `rig_background`
    // for rays that miss, both used unless the settings' light_rig is NO_RIG.
    size_t rig_lights = 0;
    Background rig_background;

    // What the loader noticed and repaired or skipped, for the user.
    std::vector<std::string> warnings;
    size_t degenerate_triangles = 0;  // dropped because no ray can hit them

    bool moving() const { return !positions_close.empty(); }
    size_t world_triangles() const { return meshes.empty() ? triangles.size() : meshes.front().first_triangle; }
    // The triangles rays meet: the world-space ones and each instance's.
    size_t placed_triangles() const {
        size_t placed = world_triangles();
        for (const Instance& instance : instances) placed += meshes[instance.mesh].triangle_count;
        return placed;
    }
    // The instance that placed a hit's triangle, or null for a world-space one.
    const Instance* instance_of(uint32_t instance) const {
        return instance == kNoInstance ? nullptr : &instances[instance];
    }
    // Of one shared mesh, in its own space, over the whole shutter interval.
    Bounds3 mesh_bounds(uint32_t mesh) const;
    // Only for a moving scene.
    vec3 position_at(uint32_t vertex, float time) const {
        return lerp_position(positions[vertex], positions_close[vertex], time);
    }

    // Of everything over the whole shutter interval.
    Bounds3 bounds() const;
    // What the scene holds in memory: vertex attributes, triangles, shared
    // meshes and instances, spheres, materials, lights and textures (their
    // texels and mip levels); the BVH is the Accelerator's (AccelStats).
    size_t stored_bytes() const;
};

}  // namespace rt
