// glTF 2.0 in three steps: gltf_loader.cpp checks the file and every file it
// references, then parses it with tinygltf; gltf_scene.cpp turns the parsed
// model's nodes and meshes into our scene, and gltf_materials.cpp its materials.
#pragma once

#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "load/format_loaders.h"
#include "load/texture_decode.h"
#include "load/third_party.h"

namespace rt {

// Extensions that may appear in `extensionsRequired`: any other one changes the
// meaning of the file in a way we would silently get wrong, so it is refused.
inline constexpr const char* kSupportedGltfExtensions[] = {"KHR_lights_punctual", "KHR_materials_transmission",
                                                          "KHR_materials_ior", "KHR_materials_emissive_strength",
                                                          "KHR_texture_transform", "EXT_texture_webp",
                                                          "KHR_mesh_quantization", "EXT_meshopt_compression",
                                                          "KHR_draco_mesh_compression", "KHR_materials_unlit"};

// What to do with a KTX2 / Basis Universal texture (KHR_texture_basisu), which
// the renderer cannot decode.
inline constexpr const char* kBasisuAdvice =
    "convert its textures to PNG first, e.g. `gltf-transform png in.glb out.glb` (glTF Transform) or "
    "`ktx extract` (KTX-Software) for each KTX2 image";

// The scene of a parsed model, its nodes moved by its first animation and by
// `motions` (gltf_poses.h). Image payloads read from URIs are still encoded, in
// tinygltf::Image::image; images in buffer views are read from there. Throws
// SceneError prefixed with `scene_name` for anything invalid.
LoadedScene build_gltf_scene(const tinygltf::Model& model, const std::string& scene_name,
                             std::span<const SceneAdditions::Motion> motions);

// glTF materials as Phong materials (docs/materials.md), each converted when a
// primitive first uses it, with its base colour texture decoded then.
class GltfMaterials {
  public:
    GltfMaterials(const tinygltf::Model& model, const std::string& scene_name, Scene& scene)
        : model_(model), name_(scene_name), scene_(scene), materials_(model.materials.size(), -1) {}

    // The scene material of glTF material `index` (kNoMaterial for -1), used by
    // the primitive `what`.
    uint32_t material(int index, const std::string& what);

  private:
    void read_surface(const tinygltf::Material& source, const std::string& label, const std::string& name,
                      Material& out);
    // The texture a textureInfo names, with its texture coordinate set and
    // KHR_texture_transform; a reference to no texture when it is left out.
    TextureRef texture(const tinygltf::TextureInfo& info, const std::string& what, Texture::Encoding encoding);
    void read_texture_transform(const tinygltf::TextureInfo& info, const std::string& what, TextureRef& ref);
    int texture_source(const tinygltf::Texture& source, const std::string& texture_name);
    // The scene texture of glTF texture `index` decoded with `encoding`, -1 when it cannot be read.
    int texture_image(size_t index, Texture::Encoding encoding);

    const tinygltf::Model& model_;
    const std::string& name_;
    Scene& scene_;
    std::vector<int> materials_;  // glTF material -> scene material, -1 until first used
    std::map<std::tuple<int, int, int, int>, int> textures_;  // (image, wrap s, wrap t, encoding) -> texture
    size_t texture_bytes_ = kMaxSceneTextureBytes;  // what the textures may still take
};

}  // namespace rt
