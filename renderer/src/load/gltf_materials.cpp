#include <algorithm>
#include <cmath>

#include <glm/gtc/type_ptr.hpp>

#include "load/gltf_loader.h"
#include "load/loader.h"

namespace rt {
namespace {

std::string at(const char* array, size_t index) {
    return std::string(array) + "[" + std::to_string(index) + "]";
}

// A number member of a material extension: `fallback` when the extension or
// the member is absent, NaN when it is not a number, so that it is refused.
double extension_number(const tinygltf::Material& material, const char* extension, const char* member,
                        double fallback) {
    const auto found = material.extensions.find(extension);
    if (found == material.extensions.end() || !found->second.IsObject() || !found->second.Has(member))
        return fallback;
    const tinygltf::Value& value = found->second.Get(member);
    return value.IsNumber() ? value.GetNumberAsDouble() : std::nan("");
}

// KHR_materials_transmission and KHR_materials_ior make a smooth dielectric
// (docs/materials.md). `label` names the material in errors and warnings.
void read_dielectric(const tinygltf::Material& source, const std::string& label, Scene& scene, Material& out) {
    const double transmission = extension_number(source, "KHR_materials_transmission", "transmissionFactor", 0.0);
    if (!std::isfinite(transmission))
        throw SceneError(label + ".extensions.KHR_materials_transmission.transmissionFactor is not a finite number");
    const double ior = extension_number(source, "KHR_materials_ior", "ior", 1.5);
    // Below 1 light would travel faster inside than in the air around it, and
    // Snell's law would refract the wrong way: no glass is like that.
    if (!std::isfinite(ior) || ior < 1.0 || ior > 1e6)
        throw SceneError(label + ".extensions.KHR_materials_ior.ior is " + shown(ior) +
                         ", expected a number from 1 to 10^6");
    out.transmission = vec3(float(std::clamp(transmission, 0.0, 1.0)));
    out.ior = float(ior);
    const auto found = source.extensions.find("KHR_materials_transmission");
    if (found != source.extensions.end() && found->second.IsObject() && found->second.Has("transmissionTexture"))
        scene.warnings.push_back(label + ".extensions.KHR_materials_transmission.transmissionTexture is ignored: "
                                         "the factor alone sets the transmission");
}

}  // namespace

uint32_t GltfMaterials::material(int index, const std::string& what) {
    // A primitive without a material gets finalisation's neutral grey, not
    // glTF's default material (see docs/materials.md).
    if (index == -1) return kNoMaterial;
    if (index < 0 || size_t(index) >= model_.materials.size())
        throw SceneError(name_ + ": " + what + ".material refers to material " + std::to_string(index) +
                         ", which does not exist");
    int& mapped = materials_[size_t(index)];
    if (mapped >= 0) return uint32_t(mapped);

    const tinygltf::Material& source = model_.materials[size_t(index)];
    const std::string name = at("materials", size_t(index));
    const tinygltf::PbrMetallicRoughness& pbr = source.pbrMetallicRoughness;
    if (pbr.baseColorFactor.size() != 4)
        throw SceneError(name_ + ": " + name + ".pbrMetallicRoughness.baseColorFactor has " +
                         std::to_string(pbr.baseColorFactor.size()) + " values, expected 4");
    bool finite = std::isfinite(pbr.metallicFactor) && std::isfinite(pbr.roughnessFactor);
    for (double v : pbr.baseColorFactor) finite = finite && std::isfinite(v);
    if (!finite)
        throw SceneError(name_ + ": " + name + ".pbrMetallicRoughness has a factor that is not finite");

    // The mapping and its reasons: docs/materials.md.
    const vec3 base(glm::clamp(glm::make_vec3(pbr.baseColorFactor.data()), 0.0, 1.0));
    Material out;
    out.name = source.name.empty() ? name : source.name;
    out.metallic_roughness = true;
    out.base_color = base;
    out.alpha = float(glm::clamp(pbr.baseColorFactor[3], 0.0, 1.0));
    out.metallic = float(glm::clamp(pbr.metallicFactor, 0.0, 1.0));
    out.roughness = float(glm::clamp(pbr.roughnessFactor, 0.0, 1.0));
    const PhongTerms terms = phong_from_metallic_roughness(out.base_color, out.metallic, out.roughness);
    out.diffuse = terms.diffuse;
    out.specular = terms.specular;
    out.shininess = terms.shininess;
    out.reflectance = terms.reflectance;
    std::string label = name_ + ": " + name;
    if (!source.name.empty()) label.append(" ").append(in_quotes(source.name));
    read_dielectric(source, label, scene_, out);
    if (pbr.baseColorTexture.index >= 0)
        out.base_color_texture =
            texture(pbr.baseColorTexture, name + ".pbrMetallicRoughness.baseColorTexture", Texture::Encoding::Srgb);
    if (pbr.metallicRoughnessTexture.index >= 0)
        out.metallic_roughness_texture = texture(pbr.metallicRoughnessTexture,
                                                 name + ".pbrMetallicRoughness.metallicRoughnessTexture",
                                                 Texture::Encoding::Linear);
    read_surface(source, label, name, out);
    out.unlit = source.extensions.count("KHR_materials_unlit") != 0;

    mapped = int(scene_.materials.size());
    scene_.materials.push_back(std::move(out));
    return uint32_t(mapped);
}

// Emission, alpha, the occlusion and normal maps and doubleSided (docs/materials.md).
void GltfMaterials::read_surface(const tinygltf::Material& source, const std::string& label, const std::string& name,
                                 Material& out) {
    if (source.emissiveFactor.size() != 3)
        throw SceneError(label + ".emissiveFactor has " + std::to_string(source.emissiveFactor.size()) +
                         " values, expected 3");
    const double strength = extension_number(source, "KHR_materials_emissive_strength", "emissiveStrength", 1.0);
    if (!std::isfinite(strength) || strength < 0.0)
        throw SceneError(label + ".extensions.KHR_materials_emissive_strength.emissiveStrength is " + shown(strength) +
                         ", expected a number of at least 0");
    vec3 emission(0.0f);
    for (int k = 0; k < 3; ++k) {
        const double e = source.emissiveFactor[size_t(k)];
        if (!std::isfinite(e)) throw SceneError(label + ".emissiveFactor has a value that is not finite");
        emission[k] = float(std::clamp(e, 0.0, 1.0) * strength);
    }
    out.emission = emission;
    if (source.emissiveTexture.index >= 0 && emission != vec3(0.0f))
        out.emissive_texture = texture(source.emissiveTexture, name + ".emissiveTexture", Texture::Encoding::Srgb);

    if (source.alphaMode == "MASK") out.alpha_mode = AlphaMode::Mask;
    else if (source.alphaMode == "BLEND") out.alpha_mode = AlphaMode::Blend;
    else if (source.alphaMode != "OPAQUE")
        throw SceneError(label + ".alphaMode is " + in_quotes(source.alphaMode) +
                         ", expected \"OPAQUE\", \"MASK\" or \"BLEND\"");
    if (!std::isfinite(source.alphaCutoff) || source.alphaCutoff < 0.0)
        throw SceneError(label + ".alphaCutoff is " + shown(source.alphaCutoff) + ", expected a number of at least 0");
    out.alpha_cutoff = float(source.alphaCutoff);
    out.double_sided = source.doubleSided;

    const tinygltf::OcclusionTextureInfo& occlusion = source.occlusionTexture;
    if (occlusion.index >= 0) {
        if (!std::isfinite(occlusion.strength))
            throw SceneError(label + ".occlusionTexture.strength is not a finite number");
        tinygltf::TextureInfo info;
        info.index = occlusion.index;
        info.texCoord = occlusion.texCoord;
        info.extensions = occlusion.extensions;
        out.occlusion_texture = texture(info, name + ".occlusionTexture", Texture::Encoding::Linear);
        out.occlusion_strength = float(std::clamp(occlusion.strength, 0.0, 1.0));
    }

    // Tangent-space data, so linear; the scale multiplies x and y. Beyond
    // +-1e4 the tilt no longer changes at float precision.
    const tinygltf::NormalTextureInfo& normal = source.normalTexture;
    if (normal.index >= 0) {
        if (!std::isfinite(normal.scale)) throw SceneError(label + ".normalTexture.scale is not a finite number");
        tinygltf::TextureInfo info;
        info.index = normal.index;
        info.texCoord = normal.texCoord;
        info.extensions = normal.extensions;
        out.normal_texture = texture(info, name + ".normalTexture", Texture::Encoding::Linear);
        out.normal_scale = float(std::clamp(normal.scale, -1e4, 1e4));
    }
}

TextureRef GltfMaterials::texture(const tinygltf::TextureInfo& info, const std::string& what,
                                  Texture::Encoding encoding) {
    const auto fail = [&](const std::string& problem) { throw SceneError(name_ + ": " + problem); };
    const auto warn = [&](const std::string& problem) { scene_.warnings.push_back(name_ + ": " + problem); };
    TextureRef ref;
    ref.texcoord = uint32_t(std::max(info.texCoord, 0));
    read_texture_transform(info, what, ref);
    if (ref.texcoord > 1) {
        warn(what + " uses TEXCOORD_" + std::to_string(ref.texcoord) +
             ", but only TEXCOORD_0 and TEXCOORD_1 are read: texture ignored");
        return ref;
    }
    if (info.index < 0 || size_t(info.index) >= model_.textures.size())
        fail(what + " refers to texture " + std::to_string(info.index) + ", which does not exist");
    ref.index = texture_image(size_t(info.index), encoding);
    return ref;
}

// KHR_texture_transform of a textureInfo into `ref`; one that is not numbers
// is refused, naming the member.
void GltfMaterials::read_texture_transform(const tinygltf::TextureInfo& info, const std::string& what,
                                           TextureRef& ref) {
    const auto found = info.extensions.find("KHR_texture_transform");
    if (found == info.extensions.end()) return;
    const std::string label = what + ".extensions.KHR_texture_transform";
    const tinygltf::Value& transform = found->second;
    if (!transform.IsObject()) throw SceneError(name_ + ": " + label + " is not an object");
    const auto number = [&](const tinygltf::Value& value, const std::string& member) {
        const double d = value.IsNumber() ? value.GetNumberAsDouble() : std::nan("");
        if (!std::isfinite(d) || std::abs(d) > 1e30)
            throw SceneError(name_ + ": " + label + "." + member + " is not a finite number");
        return float(d);
    };
    const auto pair = [&](const char* member, vec2 fallback) {
        if (!transform.Has(member)) return fallback;
        const tinygltf::Value& value = transform.Get(member);
        if (!value.IsArray() || value.ArrayLen() != 2)
            throw SceneError(name_ + ": " + label + "." + member + " is not an array of 2 numbers");
        return vec2(number(value.Get(0), member), number(value.Get(1), member));
    };
    ref.transform.offset = pair("offset", vec2(0.0f));
    ref.transform.scale = pair("scale", vec2(1.0f));
    if (transform.Has("rotation")) ref.transform.rotation = number(transform.Get("rotation"), "rotation");
    if (transform.Has("texCoord")) {
        const tinygltf::Value& set = transform.Get("texCoord");
        if (!set.IsInt() || set.GetNumberAsInt() < 0)
            throw SceneError(name_ + ": " + label + ".texCoord is not a set number (0, 1, ...)");
        ref.texcoord = uint32_t(set.GetNumberAsInt());  // overrides the textureInfo's own, as the extension says
    }
}

// The image a texture shows: EXT_texture_webp's when it has one (we read
// WebP), else its `source`. A texture with only a KHR_texture_basisu (KTX2)
// image is refused: no decoder for it ships with Debian, and a render without
// the texture would not be the scene.
int GltfMaterials::texture_source(const tinygltf::Texture& source, const std::string& texture_name) {
    const auto extension_source = [&](const char* extension) {
        const auto found = source.extensions.find(extension);
        if (found == source.extensions.end()) return -2;
        if (!found->second.IsObject() || !found->second.Has("source") || !found->second.Get("source").IsInt())
            throw SceneError(name_ + ": " + texture_name + ".extensions." + extension +
                             ".source is not an image index");
        return found->second.Get("source").GetNumberAsInt();
    };
    if (const int webp = extension_source("EXT_texture_webp"); webp != -2) return webp;
    if (source.source < 0 && extension_source("KHR_texture_basisu") != -2)
        throw SceneError(name_ + ": " + texture_name + " has only a KHR_texture_basisu (KTX2) image, which the "
                         "renderer cannot decode: " + kBasisuAdvice);
    return source.source;
}

int GltfMaterials::texture_image(size_t index, Texture::Encoding encoding) {
    const auto fail = [&](const std::string& problem) { throw SceneError(name_ + ": " + problem); };
    const auto warn = [&](const std::string& problem) { scene_.warnings.push_back(name_ + ": " + problem); };
    const tinygltf::Texture& source = model_.textures[index];
    const std::string texture_name = at("textures", index);
    const int image_index = texture_source(source, texture_name);
    if (image_index < 0) {
        warn(texture_name + " has no image we can read (an extension's?): ignored");
        return -1;
    }
    if (size_t(image_index) >= model_.images.size())
        fail(texture_name + " refers to image " + std::to_string(image_index) + ", which does not exist");

    Texture::Wrap wrap[2] = {Texture::Wrap::Repeat, Texture::Wrap::Repeat};
    if (source.sampler >= 0) {
        if (size_t(source.sampler) >= model_.samplers.size())
            fail(texture_name + ".sampler refers to sampler " + std::to_string(source.sampler) +
                 ", which does not exist");
        const tinygltf::Sampler& sampler = model_.samplers[size_t(source.sampler)];
        const int modes[2] = {sampler.wrapS, sampler.wrapT};
        for (int k = 0; k < 2; ++k) {
            switch (modes[k]) {
                case TINYGLTF_TEXTURE_WRAP_REPEAT: wrap[k] = Texture::Wrap::Repeat; break;
                case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: wrap[k] = Texture::Wrap::ClampToEdge; break;
                case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: wrap[k] = Texture::Wrap::MirroredRepeat; break;
                default:
                    fail(at("samplers", size_t(source.sampler)) + " has unknown wrap mode " +
                         std::to_string(modes[k]));
            }
        }
    }
    const auto key = std::make_tuple(image_index, int(wrap[0]), int(wrap[1]), int(encoding));
    if (const auto cached = textures_.find(key); cached != textures_.end()) return cached->second;
    int& mapped = textures_[key];
    mapped = -1;

    const tinygltf::Image& image = model_.images[size_t(image_index)];
    const std::string image_name = at("images", size_t(image_index));
    std::span<const unsigned char> bytes(image.image);
    if (image.bufferView >= 0) {
        // Checked before parsing (gltf_loader.cpp); checked again against the data.
        if (size_t(image.bufferView) >= model_.bufferViews.size()) fail(image_name + ".bufferView does not exist");
        const tinygltf::BufferView& view = model_.bufferViews[size_t(image.bufferView)];
        if (view.buffer < 0 || size_t(view.buffer) >= model_.buffers.size())
            fail(image_name + ".bufferView refers to a buffer that does not exist");
        const std::vector<unsigned char>& buffer = model_.buffers[size_t(view.buffer)].data;
        if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset)
            fail(image_name + ".bufferView does not lie inside its buffer");
        bytes = std::span<const unsigned char>(buffer).subspan(view.byteOffset, view.byteLength);
    }
    if (bytes.empty()) {
        warn(image_name + " " + in_quotes(image.uri) + " could not be read: texture ignored");
        return mapped;
    }
    std::string problem;
    std::optional<Texture> decoded =
        decode_texture(bytes, name_ + ": " + image_name, encoding, texture_bytes_, problem);
    if (!decoded) {
        warn(image_name + " " + problem + ": texture ignored");
        return mapped;
    }
    decoded->wrap_s = wrap[0];
    decoded->wrap_t = wrap[1];
    mapped = int(scene_.textures.size());
    scene_.textures.push_back(std::move(*decoded));
    return mapped;
}

}  // namespace rt
