// Scenes for the Stability tests and bench/stability_table: closed meshes whose
// edges and vertices rays aim at, lit scenes at any scale for shadow-ray
// origins, hostile geometry for non-finite pixels, and mirrors and glass for
// the depth bound.
#pragma once

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "test_meshes.h"
#include "test_scenes.h"

namespace rt::testing {

struct NamedMesh {
    std::string name;
    Scene scene;
};

// A ring torus around the z axis: `rings` segments around the axis, `sides`
// around the tube. Its inner half is saddle-shaped, so it has concave edges.
inline Scene torus(uint32_t rings, uint32_t sides, float major_radius, float minor_radius) {
    std::vector<vec3> positions, normals;
    for (uint32_t i = 0; i < rings; ++i) {
        const float phi = 2.0f * kPi * float(i) / float(rings);
        for (uint32_t j = 0; j < sides; ++j) {
            const float theta = 2.0f * kPi * float(j) / float(sides);
            const vec3 n(std::cos(theta) * std::cos(phi), std::cos(theta) * std::sin(phi), std::sin(theta));
            positions.push_back(major_radius * vec3(std::cos(phi), std::sin(phi), 0.0f) + minor_radius * n);
            normals.push_back(n);
        }
    }
    std::vector<uvec3> triangles;
    const auto vertex = [&](uint32_t i, uint32_t j) { return (i % rings) * sides + j % sides; };
    for (uint32_t i = 0; i < rings; ++i) {
        for (uint32_t j = 0; j < sides; ++j) {
            triangles.emplace_back(vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1));
            triangles.emplace_back(vertex(i, j), vertex(i + 1, j + 1), vertex(i, j + 1));
        }
    }
    Scene scene = mesh_scene(std::move(positions), std::move(triangles));
    scene.normals = std::move(normals);
    return scene;
}

// Normals pointing out of a mesh that is star-shaped around the origin.
inline Scene with_radial_normals(Scene scene) {
    for (size_t v = 0; v < scene.positions.size(); ++v) scene.normals[v] = glm::normalize(scene.positions[v]);
    return scene;
}

// Closed meshes with outward vertex normals (the leak rays are oriented by them).
inline std::vector<NamedMesh> closed_meshes() {
    return {{"icosphere", with_radial_normals(icosphere(3))},
            {"cube", with_radial_normals(cube())},
            {"torus", torus(48, 24, 1.0f, 0.4f)}};
}

// Appends `mesh` moved by `offset`, then scaled by `scale`, with `material`.
inline void append_mesh(Scene& scene, const Scene& mesh, vec3 offset, float scale, uint32_t material) {
    const uint32_t base = uint32_t(scene.positions.size());
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
        scene.positions.push_back((mesh.positions[v] + offset) * scale);
        scene.normals.push_back(mesh.normals[v]);
    }
    for (const uvec3& t : mesh.triangles) {
        scene.triangles.push_back(t + uvec3(base));
        scene.triangle_materials.push_back(material);
    }
}

// An n x n grid of unit squares in the plane y = 0, facing +y, from `corner`
// towards +x and -z, everything times `scale`.
inline void add_floor(Scene& scene, vec3 corner, uint32_t n, float scale, uint32_t material) {
    for (uint32_t i = 0; i < n; ++i)
        for (uint32_t k = 0; k < n; ++k)
            add_quad(scene, (corner + vec3(float(i), 0.0f, -float(k))) * scale, vec3(scale, 0.0f, 0.0f),
                     vec3(0.0f, 0.0f, -scale), material);
}

// A scene to check shadow rays against, at some scale: every point the camera
// sees that faces the light is, by construction, lit (`lit`) or in shadow.
struct ShadowScene {
    std::string name;
    Scene scene;
    Camera camera;
    vec3 light;
    bool lit;
};

// Away from the origin, so that the coordinates' magnitude, and the rounding
// error of every point computed from them, grows with the scale.
inline const vec3 kShadowSceneOffset(3.0f, 2.0f, -4.0f);

// Everything times `scale`: a tessellated plane, a cube and an icosphere, each
// alone, lit from above (convex, so nothing facing the light is in shadow),
// and a floor under a roof 0.05 above it, seen from between the two, where
// nothing is lit.
inline std::vector<ShadowScene> shadow_scenes(float scale) {
    const vec3 o = kShadowSceneOffset;
    const auto at = [&](vec3 p) { return (o + p) * scale; };
    std::vector<ShadowScene> scenes;
    const auto object = [&](const std::string& name, const Scene& mesh) {
        ShadowScene s{name, Scene{}, make_camera(at({3.0f, 2.5f, 4.0f}), at({0.0f, 0.0f, 0.0f}), 40.0f),
                      at({2.0f, 6.0f, 3.0f}), true};
        append_mesh(s.scene, mesh, o, scale, add_material(s.scene, vec3(0.8f)));
        scenes.push_back(std::move(s));
    };

    ShadowScene plane{"plane", Scene{}, make_camera(at({0.0f, 3.0f, 5.0f}), at({0.0f, 0.0f, -2.0f}), 60.0f),
                      at({-2.0f, 4.0f, -3.0f}), true};
    add_floor(plane.scene, o + vec3(-6.0f, 0.0f, 4.0f), 12, scale, add_material(plane.scene, vec3(0.8f)));
    scenes.push_back(std::move(plane));
    object("cube", with_radial_normals(cube()));
    object("icosphere", with_radial_normals(icosphere(3)));

    ShadowScene roof{"roof", Scene{}, make_camera(at({0.0f, 0.025f, 0.0f}), at({0.0f, 0.0f, 0.0f}), 120.0f,
                                                  vec3(0.0f, 0.0f, -1.0f)),
                     at({1.0f, 5.0f, 0.5f}), false};
    const uint32_t grey = add_material(roof.scene, vec3(0.8f));
    add_floor(roof.scene, o + vec3(-2.0f, 0.0f, 2.0f), 4, scale, grey);
    add_quad(roof.scene, at({-100.0f, 0.05f, 100.0f}), vec3(200.0f, 0.0f, 0.0f) * scale,
             vec3(0.0f, 0.0f, -200.0f) * scale, grey);
    scenes.push_back(std::move(roof));
    return scenes;
}

// The scales the shadow measurements run at: every decade from 1e-4 to 1e6.
inline std::vector<float> shadow_scales() {
    std::vector<float> scales;
    for (int e = -4; e <= 6; ++e) scales.push_back(std::pow(10.0f, float(e)));
    return scales;
}

// A whole render that must come out finite, whatever its geometry.
struct HostileCase {
    std::string name;
    Scene scene;
    Camera camera;
    RenderSettings settings;
};

inline RenderSettings hostile_settings() {
    // Odd, so that with one sample per pixel the middle row and column of
    // camera rays lie exactly in planes (degenerate_triangles).
    RenderSettings settings = make_settings(25, 25);
    settings.set_samples_per_pixel(4);
    settings.set_light_samples(4);
    settings.set_max_depth(8);
    return settings;
}

// A floor with a mirror icosphere, a box and a glass sphere on it, lit by a
// point light and a spherical light, scaled by `scale` and then moved by
// `offset`. Light intensities go with scale^2 (up to the schema's 1e30), so
// that the image would not change if floats had no limits.
inline HostileCase still_life(const std::string& name, float scale, vec3 offset = vec3(0.0f)) {
    HostileCase c{name, Scene{}, Camera{}, hostile_settings()};
    Scene& scene = c.scene;
    const auto at = [&](vec3 p) { return p * scale + offset; };
    const uint32_t grey = add_material(scene, vec3(0.7f), vec3(0.2f), 20.0f);
    const uint32_t mirror = add_material(scene, vec3(0.1f), vec3(0.0f), 1.0f, vec3(0.9f));
    const uint32_t glass = add_material(scene, vec3(0.0f));
    scene.materials[glass].transmission = vec3(1.0f);
    add_quad(scene, at({-4.0f, 0.0f, 4.0f}), vec3(8.0f, 0.0f, 0.0f) * scale, vec3(0.0f, 0.0f, -8.0f) * scale, grey);
    const uint32_t first_mesh_vertex = uint32_t(scene.positions.size());
    append_mesh(scene, with_radial_normals(icosphere(2)), {-1.5f, 1.0f, 0.0f}, 1.0f, mirror);
    append_mesh(scene, with_radial_normals(cube()), {1.5f, 1.0f, -1.0f}, 1.0f, grey);
    for (size_t v = first_mesh_vertex; v < scene.positions.size(); ++v) scene.positions[v] = at(scene.positions[v]);
    scene.spheres.push_back({at({0.0f, 0.8f, 1.5f}), 0.8f * scale, glass});
    const float intensity = float(std::min(30.0 * double(scale) * double(scale), 1e30));
    add_point_light(scene, at({2.0f, 5.0f, 3.0f}), intensity);
    Light sphere_light{"sphere light", at({-3.0f, 4.0f, 1.0f}), vec3(intensity), 0.5f * scale};
    scene.lights.push_back(sphere_light);
    c.camera = make_camera(at({0.0f, 2.0f, 6.0f}), at({0.0f, 0.5f, 0.0f}));
    return c;
}

// Triangles that a loader would drop: repeated vertices, collinear ones (also
// as a user's lerp computes them, not quite collinear after rounding), and
// slivers 1e-10 to 1e-40 high, none with usable normals. The camera looks
// along -z from the origin's level, with one sample per pixel: the middle
// row's rays then run exactly in the plane y = 0 and the middle column's in
// x = 0, where the slivers have an edge, so those rays hit them.
inline HostileCase degenerate_triangles() {
    HostileCase c = still_life("degenerate_and_sliver_triangles", 1.0f);
    c.camera = make_camera({0.0f, 0.0f, 6.0f}, {0.0f, 0.0f, 0.0f});
    c.settings.set_samples_per_pixel(1);
    Scene& scene = c.scene;
    const auto add_triangle = [&](vec3 a, vec3 b, vec3 d) {
        const uint32_t base = uint32_t(scene.positions.size());
        for (vec3 p : {a, b, d}) {
            scene.positions.push_back(p);
            scene.normals.push_back(vec3(0.0f));
        }
        scene.triangles.emplace_back(base, base + 1, base + 2);
        scene.triangle_materials.push_back(0);
    };
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    for (int i = 0; i < 400; ++i) {
        const vec3 a = vec3(2.0f * unit(rng), 1.0f + unit(rng), 2.0f + unit(rng));
        const vec3 b = a + 0.5f * vec3(unit(rng), unit(rng), unit(rng));
        add_triangle(a, a, b);
        add_triangle(a, b, a + 2.0f * (b - a));
        add_triangle(a, b, a + (0.5f + 0.5f * unit(rng)) * (b - a));
        add_triangle(a, a, a);
    }
    for (int k = 0; k < 16; ++k) {
        const float height = std::pow(10.0f, -10.0f - 2.0f * float(k));
        const float from = -2.0f + 0.25f * float(k), to = from + 0.25f;
        add_triangle({from, 0.0f, 0.0f}, {to, 0.0f, 0.0f}, {from + 0.125f, height, 0.0f});
        add_triangle({0.0f, from, -0.5f}, {0.0f, to, -0.5f}, {height, from + 0.125f, -0.5f});
    }
    return c;
}

// Rays that only graze surfaces, or run in their planes: the camera just above
// a floor looking at its horizon, then in the floor's plane, with the point
// light in it too, and in the plane of the box's top face.
inline std::vector<HostileCase> grazing_cases() {
    HostileCase grazing = still_life("grazing", 1.0f);
    grazing.camera = make_camera({0.0f, 1e-3f, 4.0f}, {0.0f, 0.0f, -4.0f}, 30.0f);
    grazing.scene.lights[0].position = {2.0f, 1e-3f, -4.0f};
    HostileCase in_plane = still_life("in_the_floor_plane", 1.0f);
    in_plane.camera = make_camera({0.0f, 0.0f, 5.0f}, {0.0f, 0.0f, -4.0f}, 60.0f);
    in_plane.scene.lights[0].position = {2.0f, 0.0f, 3.0f};
    HostileCase box_top = still_life("in_the_box_top_plane", 1.0f);
    const float top = box_top.scene.positions.back().y;  // the cube's last vertex is a top corner
    box_top.camera = make_camera({1.5f, top, 5.0f}, {1.5f, top, -1.0f}, 60.0f);
    return {std::move(grazing), std::move(in_plane), std::move(box_top)};
}

// A box turned inside out through its centre while the shutter is open: at
// mid-shutter each of its triangles is a single point.
inline HostileCase collapsing_box() {
    HostileCase c = still_life("box_collapsing_through_a_point", 1.0f);
    Scene& scene = c.scene;
    scene.positions_close = scene.positions;
    scene.normals_close = scene.normals;
    const vec3 center(0.0f, 1.0f, 3.0f);
    const size_t first = scene.positions.size();
    append_mesh(scene, with_radial_normals(cube()), center / 0.6f, 0.6f, 0);
    for (size_t v = first; v < scene.positions.size(); ++v) {
        scene.positions_close.push_back(2.0f * center - scene.positions[v]);
        scene.normals_close.push_back(-scene.normals[v]);
    }
    return c;
}

// Every hostile render: the above; the still life at every second decade of
// scale from 1e-30 to 1e30; and far from the origin, where a few hundred
// floats span it.
inline std::vector<HostileCase> hostile_cases() {
    std::vector<HostileCase> cases = grazing_cases();
    cases.push_back(degenerate_triangles());
    cases.push_back(collapsing_box());
    for (int e = -30; e <= 30; e += 2)
        cases.push_back(still_life("scale_1e" + std::to_string(e), std::pow(10.0f, float(e))));
    cases.push_back(still_life("size_1_at_1e6", 1.0f, vec3(1e6f, 1e6f, -1e6f)));
    cases.push_back(still_life("size_1e13_at_1e18", 1e13f, vec3(1e18f, -1e18f, 1e18f)));
    cases.push_back(still_life("size_1e24_at_1e30", 1e24f, vec3(1e30f, 1e30f, -1e30f)));
    return cases;
}

// A scene where a camera ray's tree of reflected and refracted rays grows
// until max_depth or min_contribution stops it.
struct DepthScene {
    std::string name;
    Scene scene;
    Camera camera;
    uint32_t branches;  // the most closest-hit rays one hit spawns
};

// Two parallel mirrors of reflectance 1, 8 apart and large enough that no ray
// leaves between them, and a camera between them looking at one.
inline DepthScene facing_mirrors() {
    DepthScene d{"facing_mirrors", Scene{}, make_camera({-3.5f, 0.1f, 0.2f}, {4.0f, 0.3f, 0.1f}, 30.0f), 1};
    const uint32_t mirror = add_material(d.scene, vec3(0.1f), vec3(0.0f), 1.0f, vec3(1.0f));
    add_quad(d.scene, {-4.0f, -500.0f, -500.0f}, {0.0f, 1000.0f, 0.0f}, {0.0f, 0.0f, 1000.0f}, mirror);
    add_quad(d.scene, {4.0f, -500.0f, -500.0f}, {0.0f, 0.0f, 1000.0f}, {0.0f, 1000.0f, 0.0f}, mirror);
    add_point_light(d.scene, {0.0f, 4.0f, 0.0f}, 10.0f);
    return d;
}

// The same with a glass sphere inside a glass sphere between the mirrors:
// every glass hit spawns both a reflection and a refraction. The glass may be
// a mirror too, as MTL's illum 7 makes it (Kr = Ks, transmission = 1 - d).
inline DepthScene nested_glass_between_mirrors(float reflectance = 0.0f, float transmission = 1.0f) {
    DepthScene d = facing_mirrors();
    d.name = reflectance == 0.0f ? "nested_glass_between_mirrors" : "nested_mirror_glass_between_mirrors";
    d.branches = 2;
    const uint32_t glass = add_material(d.scene, vec3(0.0f), vec3(0.0f), 1.0f, vec3(reflectance));
    d.scene.materials[glass].transmission = vec3(transmission);
    d.scene.spheres.push_back({vec3(0.0f), 3.0f, glass});
    d.scene.spheres.push_back({vec3(0.0f), 1.0f, glass});
    return d;
}

inline std::vector<DepthScene> depth_scenes() {
    // The last as MTL's Ks 1, d 0.1, illum 7 would have it.
    return {facing_mirrors(), nested_glass_between_mirrors(), nested_glass_between_mirrors(1.0f, 0.9f)};
}

}  // namespace rt::testing
