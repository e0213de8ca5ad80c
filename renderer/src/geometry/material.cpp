#include "geometry/material.h"

#include <algorithm>

namespace rt {

PhongTerms phong_from_metallic_roughness(vec3 base_color, float metallic, float roughness) {
    const vec3 base = glm::clamp(base_color, 0.0f, 1.0f);
    metallic = std::clamp(metallic, 0.0f, 1.0f);
    roughness = std::clamp(roughness, 0.0f, 1.0f);
    const float alpha = roughness * roughness;
    PhongTerms terms;
    terms.diffuse = base * (1.0f - metallic);
    terms.specular = glm::mix(vec3(0.04f), base, metallic);
    // Below alpha = 0.0141 the exponent exceeds the clamp's top anyway; testing
    // first keeps 2 / alpha^2 from dividing by zero.
    terms.shininess = alpha > 0.01f ? std::clamp(2.0f / (alpha * alpha) - 2.0f, 1.0f, 10000.0f) : 10000.0f;
    terms.reflectance = terms.specular * (1.0f - roughness) * (1.0f - roughness);
    return terms;
}

}  // namespace rt
