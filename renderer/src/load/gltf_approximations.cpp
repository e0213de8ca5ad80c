#include "load/gltf_approximations.h"

#include <algorithm>
#include <iterator>
#include <map>

#include "load/gltf_loader.h"
#include "load/scene_files.h"

namespace rt {
namespace {

// What a render shows without each extension we know of but do not read.
// Required ones never get here: check_document() refuses them.
const std::map<std::string, std::string>& what_is_lost() {
    static const std::map<std::string, std::string> lost = {
        {"KHR_materials_clearcoat", "rendered without the clearcoat layer"},
        {"KHR_materials_sheen", "rendered without sheen"},
        {"KHR_materials_specular", "rendered with the core material's specular strength and colour"},
        {"KHR_materials_iridescence", "rendered without thin-film iridescence"},
        {"KHR_materials_anisotropy", "rendered with isotropic highlights"},
        {"KHR_materials_volume", "rendered without attenuation inside transmissive volumes"},
        {"KHR_materials_dispersion", "rendered with one index of refraction for every colour"},
        {"KHR_materials_diffuse_transmission", "rendered without diffuse transmission"},
        {"KHR_materials_variants", "rendered with the default materials, not the variants"},
        {"KHR_materials_pbrSpecularGlossiness", "rendered with each material's metallic-roughness fallback"},
        {"KHR_animation_pointer", "animated properties other than node transforms are not followed"},
        {"KHR_xmp_json_ld", "the metadata is not shown"},
        {"KHR_node_visibility", "hidden nodes are drawn"},
        {"KHR_node_selectability", "nothing to render: selection is for viewers"},
        {"KHR_node_hoverability", "nothing to render: hovering is for viewers"},
        {"KHR_interactivity", "rendered as authored, without its behaviour graphs"},
        {"KHR_gaussian_splatting", "the splats are not rendered"},
        {"EXT_mesh_gpu_instancing", "each instanced mesh is drawn once, at its node, without its instances"},
        {"EXT_texture_avif", "textures use their fallback images, where they have one"},
        {"EXT_lights_image_based", "rendered without the image-based light"},
    };
    return lost;
}

bool supported(const std::string& extension) {
    return std::find(std::begin(kSupportedGltfExtensions), std::end(kSupportedGltfExtensions), extension) !=
           std::end(kSupportedGltfExtensions);
}

}  // namespace

std::vector<std::string> approximation_warnings(const tinygltf::Model& model, const std::string& name) {
    std::vector<std::string> warnings;
    for (const std::string& extension : model.extensionsUsed) {
        if (supported(extension)) continue;
        const auto known = what_is_lost().find(extension);
        warnings.push_back(name + ": uses the glTF extension " + in_quotes(extension) +
                           ", which is not supported: " +
                           (known != what_is_lost().end() ? known->second : std::string("rendered without it")));
    }
    if (!model.skins.empty())
        warnings.push_back(name + ": has " + std::to_string(model.skins.size()) +
                           " skin(s), which are not supported: skinned meshes render in their bind pose");
    for (size_t m = 0; m < model.meshes.size(); ++m)
        for (const tinygltf::Primitive& primitive : model.meshes[m].primitives)
            if (!primitive.targets.empty()) {
                warnings.push_back(name + ": meshes[" + std::to_string(m) +
                                   "] has morph targets, which are not supported: rendered in its base shape");
                break;
            }
    return warnings;
}

}  // namespace rt
