// Phong materials and their textures. How glTF's metallic/roughness and OBJ's
// MTL map onto these fields is written down in docs/materials.md.
#pragma once

#include <string>
#include <vector>

#include "util/math.h"

namespace rt {

// An image in linear RGB, sampled bilinearly.
struct Texture {
    enum class Wrap { Repeat, ClampToEdge, MirroredRepeat };

    int width = 0;
    int height = 0;
    std::vector<vec3> texels;  // row-major, row 0 at v = 0 (top of the image)
    Wrap wrap_s = Wrap::Repeat;
    Wrap wrap_t = Wrap::Repeat;

    vec3 sample(vec2 uv) const;
};

struct Material {
    std::string name;
    vec3 diffuse{0.8f};       // Kd, albedo of the Lambertian term
    vec3 specular{0.0f};      // Ks, weight of the normalized Phong lobe
    float shininess = 1.0f;   // Ns, Phong exponent
    vec3 reflectance{0.0f};   // Kr, weight of the mirror-reflected ray
    // Share of the light that meets a smooth dielectric interface instead of
    // the Phong surface: 0 is opaque. Fresnel splits it between a reflected and
    // a refracted ray; the Phong terms keep 1 - transmission.
    vec3 transmission{0.0f};
    float ior = 1.5f;         // index of refraction inside, relative to outside
    int diffuse_texture = -1; // index into Scene::textures; multiplies `diffuse`
};

}  // namespace rt
