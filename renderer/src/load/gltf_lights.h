// One KHR_lights_punctual light of a glTF model, placed by its node.
#pragma once

#include <string>

#include "geometry/scene.h"
#include "load/third_party.h"
#include "util/math.h"

namespace rt {

// The light `light` (named `name` in messages) on a node whose world transform
// is `world`: point and spot lights at its origin, spot and directional lights
// along its -Z. A directional light's `extras.rt.angular_diameter` (degrees)
// softens its shadows. Throws std::invalid_argument naming what is wrong.
Light read_gltf_light(const tinygltf::Light& light, const std::string& name, const dmat4& world);

}  // namespace rt
