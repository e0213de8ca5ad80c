#include "geometry/surface.h"

#include "geometry/sphere.h"
#include "geometry/triangle.h"
#include "geometry/triangle_corners.h"

namespace rt {
namespace {

// Twice the area of the uv triangle (a, b, c).
float uv_area(vec2 a, vec2 b, vec2 c) {
    const vec2 e1 = b - a, e2 = c - a;
    return std::abs(e1.x * e2.y - e1.y * e2.x);
}

// The triangle's uv area per world area for each texture coordinate set,
// which turns a ray cone's width into texels (texture_lookup.h). Constant
// over the triangle; `world_area` is twice its area, like uv_area's.
void set_area_ratios(const Scene& scene, uvec3 tri, double world_area, SurfaceHit& s) {
    if (!(world_area > 0.0)) return;
    if (!scene.texcoords.empty())
        s.uv_area_ratio = float(uv_area(scene.texcoords[tri.x], scene.texcoords[tri.y], scene.texcoords[tri.z]) /
                                world_area);
    if (!scene.texcoords1.empty())
        s.uv1_area_ratio = float(uv_area(scene.texcoords1[tri.x], scene.texcoords1[tri.y], scene.texcoords1[tri.z]) /
                                 world_area);
}

}  // namespace

SurfaceHit surface_at(const Scene& scene, const Ray& ray, const Hit& hit, TriangleCorners* corners) {
    SurfaceHit s;
    s.time = ray.time;
    const size_t triangle_count = scene.triangles.size();
    if (hit.primitive >= triangle_count) {
        const Sphere& sphere = scene.spheres[hit.primitive - triangle_count];
        s.p = sphere_point(sphere, ray, hit.t, s.p_error, s.ng);
        s.ns = s.ng;
        s.material = sphere.material;
        return s;
    }

    const TriangleCorners c = triangle_corners(scene, hit, ray.time);
    if (corners) *corners = c;
    const uvec3 tri = c.vertices;
    const vec3 p0 = c.p[0], p1 = c.p[1], p2 = c.p[2];
    const float b0 = 1.0f - hit.u - hit.v;
    s.p = b0 * p0 + hit.u * p1 + hit.v * p2;
    s.p_error = gamma_bound(7) * (glm::abs(b0 * p0) + glm::abs(hit.u * p1) + glm::abs(hit.v * p2)) + c.placement_error;
    // Zero only for a triangle with no area, which the loaders drop; one built
    // otherwise, or moving through such a pose, faces the ray that found it.
    const dvec3 area = area_normal(p0, p1, p2);
    s.ng = area != dvec3(0.0) ? vec3(glm::normalize(area)) : -glm::normalize(ray.direction);

    s.ns = try_normalize(b0 * c.n[0] + hit.u * c.n[1] + hit.v * c.n[2]).value_or(s.ng);
    if (!scene.texcoords.empty())
        s.uv = b0 * scene.texcoords[tri.x] + hit.u * scene.texcoords[tri.y] + hit.v * scene.texcoords[tri.z];
    if (!scene.texcoords1.empty())
        s.uv1 = b0 * scene.texcoords1[tri.x] + hit.u * scene.texcoords1[tri.y] + hit.v * scene.texcoords1[tri.z];
    if (!scene.colors.empty())
        s.color = b0 * scene.colors[tri.x] + hit.u * scene.colors[tri.y] + hit.v * scene.colors[tri.z];
    s.material = scene.triangle_materials[hit.primitive];
    if (!scene.textures.empty()) set_area_ratios(scene, tri, glm::length(area), s);
    return s;
}

void face_viewer(SurfaceHit& s, vec3 towards_viewer) {
    // The winding may disagree with the authored normals; the normals win.
    if (glm::dot(s.ns, s.ng) < 0.0f) s.ng = -s.ng;
    if (glm::dot(s.ng, towards_viewer) < 0.0f) {
        s.ng = -s.ng;
        s.ns = -s.ns;
    }
    if (glm::dot(s.ns, towards_viewer) <= 0.0f) s.ns = s.ng;
    s.n_smooth = s.ns;
}

}  // namespace rt
