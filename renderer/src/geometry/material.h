// Phong materials, and the glTF inputs that vary them per texel. How glTF's
// metallic/roughness and OBJ's MTL map onto these fields is written down in
// docs/materials.md.
#pragma once

#include <string>
#include <vector>

#include "geometry/texture.h"
#include "util/math.h"

namespace rt {

// glTF's alphaMode. OPAQUE ignores alpha; MASK makes texels below the cutoff
// holes for every ray; BLEND lets (1 - alpha) of the light through, unbent.
enum class AlphaMode : uint8_t { Opaque, Mask, Blend };

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

    // glTF's metallic-roughness inputs, kept where a texture varies them per
    // texel: the Phong terms above are then derived at each hit, through the
    // same mapping (phong_from_metallic_roughness). For OBJ, and for glTF
    // materials without such textures, `diffuse`.. `reflectance` are all there is.
    bool metallic_roughness = false;
    vec3 base_color{0.8f};
    float metallic = 0.0f;
    float roughness = 1.0f;

    // Multiplies the base colour (glTF) or `diffuse` (OBJ), and with its alpha
    // the material's `alpha`.
    TextureRef base_color_texture;
    TextureRef metallic_roughness_texture;  // B scales metallic, G roughness
    TextureRef normal_texture;              // tangent-space, scaled by normal_scale
    float normal_scale = 1.0f;
    TextureRef occlusion_texture;           // R; darkens the default rig's fill only
    float occlusion_strength = 1.0f;
    vec3 emission{0.0f};                    // linear radiance, emissiveFactor times strength
    TextureRef emissive_texture;            // multiplies `emission`

    AlphaMode alpha_mode = AlphaMode::Opaque;
    float alpha = 1.0f;                     // base colour alpha
    float alpha_cutoff = 0.5f;              // MASK: texels below it are holes
    bool double_sided = false;
    // KHR_materials_unlit: the base colour (× texture × vertex colour) is the
    // radiance the surface sends, whatever lights it.
    bool unlit = false;

    bool textured() const {
        return bool(base_color_texture) || bool(metallic_roughness_texture) || bool(normal_texture) ||
               bool(occlusion_texture) || bool(emissive_texture);
    }
};

// The Phong terms of a glTF metallic-roughness surface (docs/materials.md).
struct PhongTerms {
    vec3 diffuse;
    vec3 specular;
    float shininess;
    vec3 reflectance;
};
PhongTerms phong_from_metallic_roughness(vec3 base_color, float metallic, float roughness);

}  // namespace rt
