#include "geometry/surface_material.h"

#include "geometry/texture_lookup.h"

namespace rt {
namespace {

float coverage_of(const Material& m, float alpha) {
    switch (m.alpha_mode) {
        case AlphaMode::Opaque: return 1.0f;
        case AlphaMode::Mask: return alpha >= m.alpha_cutoff ? 1.0f : 0.0f;
        case AlphaMode::Blend: return glm::clamp(alpha, 0.0f, 1.0f);
    }
    return 1.0f;
}

// An unlit surface has no term that light could scale: it only emits, and it
// still stops rays as its alpha says (so it casts shadows, as in three.js).
SurfaceMaterial unlit_material(const Scene& scene, const Material& m, const SurfaceHit& s) {
    SurfaceMaterial out;
    const glm::vec4 texel = lookup(scene, m.base_color_texture, s) * s.color;
    out.coverage = coverage_of(m, m.alpha * texel.a);
    out.emission = m.base_color * vec3(texel);
    return out;
}

}  // namespace

SurfaceMaterial surface_material(const Scene& scene, const Material& m, const SurfaceHit& s) {
    if (m.unlit) return unlit_material(scene, m, s);
    SurfaceMaterial out;
    out.diffuse = m.diffuse;
    out.specular = m.specular;
    out.shininess = m.shininess;
    out.reflectance = m.reflectance;
    out.emission = m.emission;
    const bool coloured = s.color != glm::vec4(1.0f);
    if (!m.textured() && !coloured && m.alpha_mode == AlphaMode::Opaque) return out;

    // glTF multiplies the base colour factor, texel and vertex colour, alpha too.
    const glm::vec4 texel = lookup(scene, m.base_color_texture, s) * s.color;
    out.coverage = coverage_of(m, m.alpha * texel.a);
    if (m.metallic_roughness) {
        const glm::vec4 mr = lookup(scene, m.metallic_roughness_texture, s);
        const PhongTerms terms =
            phong_from_metallic_roughness(m.base_color * vec3(texel), m.metallic * mr.b, m.roughness * mr.g);
        out.diffuse = terms.diffuse;
        out.specular = terms.specular;
        out.shininess = terms.shininess;
        out.reflectance = terms.reflectance;
    } else {
        out.diffuse = m.diffuse * vec3(texel);
    }
    if (m.emissive_texture) out.emission *= vec3(lookup(scene, m.emissive_texture, s));
    if (m.occlusion_texture)
        out.occlusion = 1.0f + m.occlusion_strength * (lookup(scene, m.occlusion_texture, s).r - 1.0f);
    return out;
}

float surface_coverage(const Scene& scene, const Material& m, const SurfaceHit& s) {
    if (m.alpha_mode == AlphaMode::Opaque) return 1.0f;
    return coverage_of(m, m.alpha * lookup(scene, m.base_color_texture, s).a * s.color.a);
}

float triangle_coverage(const Scene& scene, uint32_t triangle, float u, float v) {
    const Material& m = scene.materials[scene.triangle_materials[triangle]];
    if (m.alpha_mode == AlphaMode::Opaque) return 1.0f;
    const uvec3 tri = scene.triangles[triangle];
    const float w = 1.0f - u - v;
    const auto at = [&](const auto& attribute) { return w * attribute[tri.x] + u * attribute[tri.y] + v * attribute[tri.z]; };
    SurfaceHit s;
    if (!scene.texcoords.empty()) s.uv = at(scene.texcoords);
    if (!scene.texcoords1.empty()) s.uv1 = at(scene.texcoords1);
    if (!scene.colors.empty()) s.color = at(scene.colors);
    return surface_coverage(scene, m, s);
}

}  // namespace rt
