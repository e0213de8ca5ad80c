// Scene loading: glTF 2.0 (.gltf, .glb) and OBJ + MTL, plus the sidecar
// `<scene>.rt.json` (proto rt.SceneExtras) for what those formats cannot say.
//
// Everything a user hands us is hostile until validated: every reference must
// stay inside the scene file's folder, every index and count is checked, and a
// bad file throws SceneError with a message naming the file and the element.
#pragma once

#include <cstddef>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <string_view>

#include "geometry/scene.h"
#include "load/scene_files.h"

namespace rt {

// Format by extension: .gltf, .glb, .obj.
Scene load_scene(const std::filesystem::path& file);

// A scene held in memory: a .glb, or a .gltf/.obj that references no other file
// (data: URIs are fine). `file_name` gives the format by its extension and names
// the scene in messages.
Scene load_scene_from_memory(std::span<const std::byte> data, std::string_view file_name);

}  // namespace rt
