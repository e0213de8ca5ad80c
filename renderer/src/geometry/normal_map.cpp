#include "geometry/normal_map.h"

#include <cmath>

#include "geometry/texture_lookup.h"

namespace rt {
namespace {

// How far the bent normal must face the viewer at least: a grazing but
// visible highlight rather than a normal at exactly 90 degrees.
constexpr float kMinFacing = 0.01f;

}  // namespace

vec3 bend_normal(vec3 n, glm::vec4 tangent, vec3 texel, float scale) {
    const vec3 t3(tangent);
    const std::optional<vec3> t = try_normalize(t3 - n * glm::dot(n, t3));
    if (!t || tangent.w == 0.0f) return n;
    const vec3 b = (tangent.w < 0.0f ? -1.0f : 1.0f) * glm::cross(n, *t);
    const vec3 m = 2.0f * texel - vec3(1.0f);
    return try_normalize(*t * (m.x * scale) + b * (m.y * scale) + n * m.z).value_or(n);
}

glm::vec4 tangent_at(const Scene& scene, const Hit& hit, float time) {
    if (scene.tangents.empty() || hit.primitive >= scene.triangles.size()) return glm::vec4(0.0f);
    const uvec3 tri = scene.triangles[hit.primitive];
    const glm::vec4 t0 = scene.tangents[tri.x], t1 = scene.tangents[tri.y], t2 = scene.tangents[tri.z];
    if (t0.w == 0.0f || t1.w == 0.0f || t2.w == 0.0f) return glm::vec4(0.0f);
    const glm::vec4 t = (1.0f - hit.u - hit.v) * t0 + hit.u * t1 + hit.v * t2;
    const float w = t.w < 0.0f ? -1.0f : 1.0f;
    const Instance* instance = scene.instance_of(hit.instance);
    if (!instance) return glm::vec4(vec3(t), w);
    // A tangent goes with the vertices (the linear part, as the loader places
    // them); a mirroring instance flips the bitangent, so w too. A moving
    // instance mirrors all the shutter long or never (the loader's check).
    const glm::mat3 linear = instance->moving ? instance->at(time).to_world.linear : instance->to_world.linear;
    const bool mirrored = glm::determinant(linear) < 0.0f;
    return glm::vec4(linear * vec3(t), mirrored ? -w : w);
}

void apply_normal_map(const Scene& scene, const Material& m, const Hit& hit, vec3 authored, vec3 wo,
                      SurfaceHit& s) {
    const glm::vec4 tangent = tangent_at(scene, hit, s.time);
    if (tangent.w == 0.0f) return;
    const vec3 bent = bend_normal(authored, tangent, vec3(lookup(scene, m.normal_texture, s)), m.normal_scale);
    // face_viewer turned both normals to the viewer's side; the bent one
    // follows the side the authored normal ended up on.
    vec3 n = glm::dot(authored, s.ng) < 0.0f ? -bent : bent;
    const float facing = glm::dot(n, wo);
    if (facing < kMinFacing) n = try_normalize(n + (kMinFacing - facing) * wo).value_or(s.ns);
    s.ns = n;
}

}  // namespace rt
