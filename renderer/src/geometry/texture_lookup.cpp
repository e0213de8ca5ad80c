#include "geometry/texture_lookup.h"

#include <cmath>

namespace rt {

float texture_lod(const Texture& texture, const TextureRef& ref, const SurfaceHit& s) {
    // RTG 2019, ch. 20, ray cones: lambda = log2(w / |cos theta|) + 0.5 log2(t_a / p_a),
    // t_a the triangle's texel area (texture size times its uv area, which
    // the transform's scale stretches), p_a its world area. Computed as one
    // log2 of the squared footprint, in texels of level 0.
    const float ratio = ref.texcoord == 1 ? s.uv1_area_ratio : s.uv_area_ratio;
    const float footprint = s.cone_width / s.cos_incidence;
    const float texel_area = float(texture.width) * float(texture.height) * ratio *
                             std::abs(ref.transform.scale.x * ref.transform.scale.y);
    // Without a cone or texture coordinates: -inf, level 0.
    return 0.5f * std::log2(footprint * footprint * texel_area);
}

glm::vec4 lookup(const Scene& scene, const TextureRef& ref, const SurfaceHit& s) {
    if (!ref || size_t(ref.index) >= scene.textures.size()) return glm::vec4(1.0f);
    const Texture& texture = scene.textures[size_t(ref.index)];
    const vec2 uv = ref.texcoord == 1 ? s.uv1 : s.uv;
    const vec2 st = ref.transform.identity() ? uv : ref.transform.apply(uv);
    return texture.sample(st, s.cone_width > 0.0f ? texture_lod(texture, ref, s) : 0.0f);
}

}  // namespace rt
