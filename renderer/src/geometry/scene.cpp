#include "geometry/scene.h"

namespace rt {

namespace {

void extend_by_triangles(const Scene& scene, size_t first, size_t count, Bounds3& b) {
    for (size_t i = first; i < first + count; ++i)
        for (int k = 0; k < 3; ++k) {
            b.extend(scene.positions[scene.triangles[i][k]]);
            if (scene.moving()) b.extend(scene.positions_close[scene.triangles[i][k]]);
        }
}

}  // namespace

Bounds3 Scene::mesh_bounds(uint32_t mesh) const {
    Bounds3 b;
    extend_by_triangles(*this, meshes[mesh].first_triangle, meshes[mesh].triangle_count, b);
    return b;
}

Bounds3 Scene::bounds() const {
    Bounds3 b;
    if (meshes.empty()) {
        for (const vec3& p : positions) b.extend(p);
        for (const vec3& p : positions_close) b.extend(p);
    } else {
        extend_by_triangles(*this, 0, world_triangles(), b);
        std::vector<Bounds3> local(meshes.size());
        for (uint32_t m = 0; m < meshes.size(); ++m) local[m] = mesh_bounds(m);
        for (const Instance& instance : instances) {
            b.extend(instance.to_world.box(local[instance.mesh]));
            if (instance.moving) b.extend(instance.to_world_close.box(local[instance.mesh]));
        }
    }
    for (const Sphere& s : spheres) {
        b.extend(s.center - vec3(s.radius));
        b.extend(s.center + vec3(s.radius));
    }
    return b;
}

size_t Scene::stored_bytes() const {
    const auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
    size_t total = bytes(positions) + bytes(normals) + bytes(texcoords) + bytes(texcoords1) + bytes(colors) +
                   bytes(tangents) + bytes(positions_close) + bytes(normals_close) + bytes(triangles) +
                   bytes(triangle_materials) + bytes(meshes) + bytes(instances) + bytes(spheres) + bytes(materials) +
                   bytes(lights) + bytes(cameras);
    for (const Texture& texture : textures) total += texture.bytes();
    total += bytes(instance_names);
    for (const std::string& name : instance_names) total += name.capacity();
    return total;
}

}  // namespace rt
