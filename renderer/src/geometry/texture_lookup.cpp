#include "geometry/texture_lookup.h"

namespace rt {

glm::vec4 lookup(const Scene& scene, const TextureRef& ref, const SurfaceHit& s) {
    if (!ref || size_t(ref.index) >= scene.textures.size()) return glm::vec4(1.0f);
    const vec2 uv = ref.texcoord == 1 ? s.uv1 : s.uv;
    const vec2 st = ref.transform.identity() ? uv : ref.transform.apply(uv);
    return glm::vec4(scene.textures[size_t(ref.index)].sample(st), 1.0f);
}

}  // namespace rt
