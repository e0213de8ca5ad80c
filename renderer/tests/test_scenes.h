// Small scenes built in code for the shading, acne and determinism tests.
#pragma once

#include "geometry/scene.h"
#include "integrator/render.h"

namespace rt::testing {

inline uint32_t add_material(Scene& scene, vec3 diffuse, vec3 specular = vec3(0.0f), float shininess = 1.0f,
                             vec3 reflectance = vec3(0.0f)) {
    Material m;
    m.name = "material" + std::to_string(scene.materials.size());
    m.diffuse = diffuse;
    m.specular = specular;
    m.shininess = shininess;
    m.reflectance = reflectance;
    scene.materials.push_back(m);
    return uint32_t(scene.materials.size() - 1);
}

// A quad from corner c with edges e1, e2, facing along cross(e1, e2).
inline void add_quad(Scene& scene, vec3 c, vec3 e1, vec3 e2, uint32_t material) {
    const uint32_t base = uint32_t(scene.positions.size());
    const vec3 n = glm::normalize(glm::cross(e1, e2));
    for (vec3 p : {c, c + e1, c + e1 + e2, c + e2}) {
        scene.positions.push_back(p);
        scene.normals.push_back(n);
    }
    scene.triangles.push_back({base, base + 1, base + 2});
    scene.triangles.push_back({base, base + 2, base + 3});
    scene.triangle_materials.push_back(material);
    scene.triangle_materials.push_back(material);
}

inline void add_point_light(Scene& scene, vec3 position, float intensity) {
    Light light;
    light.name = "light" + std::to_string(scene.lights.size());
    light.position = position;
    light.intensity = vec3(intensity);
    scene.lights.push_back(light);
}

inline Camera make_camera(vec3 position, vec3 target, float fov_y = 45.0f, vec3 up = vec3(0.0f, 1.0f, 0.0f)) {
    Camera camera;
    for (int i = 0; i < 3; ++i) {
        camera.add_position(position[i]);
        camera.add_target(target[i]);
        camera.add_up(up[i]);
    }
    camera.set_fov_y(fov_y);
    return camera;
}

// The colour of one pixel, rendered as a tile of its own.
inline vec3 render_pixel(const Renderer& renderer, uint32_t x, uint32_t y) {
    float rgb[3];
    renderer.render_tile({x, y, 1, 1}, rgb);
    return {rgb[0], rgb[1], rgb[2]};
}

inline RenderSettings make_settings(uint32_t width, uint32_t height) {
    RenderSettings settings;
    settings.set_width(width);
    settings.set_height(height);
    return settings;
}

// A floor (y = 0) with a sphere resting on it and a point light above:
// everything scaled by `scale`, the light's intensity by scale^2 so that
// the image does not depend on the scale.
inline Scene floor_and_sphere(float scale) {
    Scene scene;
    const uint32_t grey = add_material(scene, vec3(0.7f), vec3(0.2f), 20.0f);
    add_quad(scene, vec3(-4.0f, 0.0f, 4.0f) * scale, vec3(8.0f, 0.0f, 0.0f) * scale, vec3(0.0f, 0.0f, -8.0f) * scale,
             grey);
    scene.spheres.push_back({vec3(0.0f, 1.0f, 0.0f) * scale, 1.0f * scale, add_material(scene, vec3(0.3f, 0.5f, 0.8f))});
    add_point_light(scene, vec3(2.0f, 5.0f, 3.0f) * scale, 30.0f * scale * scale);
    return scene;
}

}  // namespace rt::testing
