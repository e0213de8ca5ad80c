// What a glTF file asks for that the renderer draws only approximately, told
// to the user as warnings (docs/gltf.md lists each with its words): extensions
// it uses but does not require and that we do not read, skins and morph targets.
#pragma once

#include <string>
#include <vector>

#include "load/third_party.h"

namespace rt {

// One warning per approximation, each starting with `name` (the file's).
std::vector<std::string> approximation_warnings(const tinygltf::Model& model, const std::string& name);

}  // namespace rt
