#include "export/glb_materials.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "export/texture_encode.h"

namespace rt {
namespace {

using Json = nlohmann::json;

int wrap_mode(Texture::Wrap wrap) {
    switch (wrap) {
        case Texture::Wrap::ClampToEdge: return 33071;
        case Texture::Wrap::MirroredRepeat: return 33648;
        case Texture::Wrap::Repeat: break;
    }
    return 10497;
}

// The glTF roughness whose Beckmann lobe has the Phong exponent `shininess`:
// docs/materials.md's shininess = 2 / alpha^2 - 2 with alpha = roughness^2,
// solved for roughness, so the loader reads the same exponent back.
float roughness_of(float shininess) {
    const float alpha = std::sqrt(2.0f / (std::max(shininess, 0.0f) + 2.0f));
    return std::sqrt(alpha);
}

// One pass over the materials. It carries what a single material cannot know:
// which textures are embedded already and which extensions some material used,
// to be declared once at the end.
class MaterialWriter {
  public:
    MaterialWriter(const Scene& scene, GlbWriter& writer)
        : scene_(scene), writer_(writer), texture_indices_(scene.textures.size(), -1) {}

    void run();

  private:
    int add_texture(int scene_texture);
    Json texture_info(const TextureRef& ref);
    Json pbr_of(const Material& m);
    void add_surface(const Material& m, Json& material);

    const Scene& scene_;
    GlbWriter& writer_;
    std::vector<int> texture_indices_;  // scene texture -> glTF texture, -1 until used
    bool emissive_strength_ = false;    // some material needs KHR_materials_emissive_strength
    bool texture_transform_ = false;    // some texture reference needs KHR_texture_transform
    bool unlit_ = false;                // some material is KHR_materials_unlit
};

int MaterialWriter::add_texture(int scene_texture) {
    int& index = texture_indices_[size_t(scene_texture)];
    if (index >= 0) return index;
    const Texture& texture = scene_.textures[size_t(scene_texture)];
    const std::vector<unsigned char> png = encode_png(texture);
    const int view = writer_.add_view(png.data(), png.size(), 0);
    const int image = writer_.append("images", {{"bufferView", view}, {"mimeType", "image/png"}});
    // Trilinear, as the renderer samples it (its ray cones pick the level
    // where the viewer's GPU uses screen-space derivatives).
    const int sampler = writer_.append("samplers", {{"magFilter", kGltfLinear},
                                                    {"minFilter", kGltfLinearMipmapLinear},
                                                    {"wrapS", wrap_mode(texture.wrap_s)},
                                                    {"wrapT", wrap_mode(texture.wrap_t)}});
    index = writer_.append("textures", {{"sampler", sampler}, {"source", image}});
    return index;
}

Json MaterialWriter::texture_info(const TextureRef& ref) {
    Json info = {{"index", add_texture(ref.index)}};
    if (ref.texcoord != 0) info["texCoord"] = ref.texcoord;
    if (!ref.transform.identity()) {
        const TextureTransform& t = ref.transform;
        info["extensions"]["KHR_texture_transform"] = {
            {"offset", {t.offset.x, t.offset.y}}, {"rotation", t.rotation}, {"scale", {t.scale.x, t.scale.y}}};
        // three.js reads the transform's own texCoord, not the textureInfo's, when it has one.
        if (ref.texcoord != 0) info["extensions"]["KHR_texture_transform"]["texCoord"] = ref.texcoord;
        texture_transform_ = true;
    }
    return info;
}

// glTF's own inputs where the material came from them; an OBJ's Phong terms
// as the nearest dielectric.
Json MaterialWriter::pbr_of(const Material& m) {
    const vec3 base = glm::clamp(m.metallic_roughness ? m.base_color : m.diffuse, 0.0f, 1.0f);
    Json pbr = {{"baseColorFactor", {base.r, base.g, base.b, m.alpha}},
                {"metallicFactor", m.metallic_roughness ? m.metallic : 0.0f},
                {"roughnessFactor", m.metallic_roughness ? m.roughness : roughness_of(m.shininess)}};
    if (has_texture(scene_, m.base_color_texture)) pbr["baseColorTexture"] = texture_info(m.base_color_texture);
    if (has_texture(scene_, m.metallic_roughness_texture))
        pbr["metallicRoughnessTexture"] = texture_info(m.metallic_roughness_texture);
    return pbr;
}

// Emission, alpha and the occlusion and normal maps, as three.js's GLTFLoader reads them.
void MaterialWriter::add_surface(const Material& m, Json& material) {
    if (m.emission != vec3(0.0f)) {
        // emissiveFactor stops at 1; the rest goes into the strength.
        const float strength = std::max(max_component(m.emission), 1.0f);
        material["emissiveFactor"] = gltf_array3(m.emission / strength);
        if (strength > 1.0f) {
            material["extensions"]["KHR_materials_emissive_strength"] = {{"emissiveStrength", strength}};
            emissive_strength_ = true;
        }
        if (has_texture(scene_, m.emissive_texture)) material["emissiveTexture"] = texture_info(m.emissive_texture);
    }
    if (m.alpha_mode == AlphaMode::Mask) {
        material["alphaMode"] = "MASK";
        material["alphaCutoff"] = m.alpha_cutoff;
    } else if (m.alpha_mode == AlphaMode::Blend) {
        material["alphaMode"] = "BLEND";
    }
    if (m.double_sided) material["doubleSided"] = true;
    if (has_texture(scene_, m.occlusion_texture)) {
        material["occlusionTexture"] = texture_info(m.occlusion_texture);
        material["occlusionTexture"]["strength"] = m.occlusion_strength;
    }
    if (has_texture(scene_, m.normal_texture)) {
        material["normalTexture"] = texture_info(m.normal_texture);
        material["normalTexture"]["scale"] = m.normal_scale;
    }
}

void MaterialWriter::run() {
    bool transmissive = false;
    for (const Material& m : scene_.materials) {
        Json material = {{"pbrMetallicRoughness", pbr_of(m)}};
        add_surface(m, material);
        if (!m.name.empty()) material["name"] = m.name;
        if (m.unlit) {
            material["extensions"]["KHR_materials_unlit"] = Json::object();
            unlit_ = true;
        }
        material["extras"]["rt"]["phong"] = {{"diffuse", gltf_array3(m.diffuse)},
                                             {"specular", gltf_array3(m.specular)},
                                             {"shininess", m.shininess},
                                             {"reflectance", gltf_array3(m.reflectance)}};
        // Glass as glTF has it, for viewers; opaque materials stay as they were.
        if (m.transmission != vec3(0.0f)) {
            material["extensions"]["KHR_materials_transmission"] = {
                {"transmissionFactor", max_component(m.transmission)}};
            material["extensions"]["KHR_materials_ior"] = {{"ior", m.ior}};
            transmissive = true;
        }
        writer_.append("materials", std::move(material));
    }
    // Created on first use: glTF forbids an empty extensionsUsed.
    const auto use = [&](const char* extension) { writer_.doc()["extensionsUsed"].push_back(extension); };
    if (transmissive)
        for (const char* extension : {"KHR_materials_transmission", "KHR_materials_ior"}) use(extension);
    if (emissive_strength_) use("KHR_materials_emissive_strength");
    if (texture_transform_) use("KHR_texture_transform");
    if (unlit_) use("KHR_materials_unlit");
}

}  // namespace

bool has_texture(const Scene& scene, const TextureRef& ref) {
    return ref && size_t(ref.index) < scene.textures.size();
}

void add_materials(const Scene& scene, GlbWriter& writer) { MaterialWriter(scene, writer).run(); }

}  // namespace rt
