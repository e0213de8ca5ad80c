// How a glTF camera projects: its perspective or orthographic parameters as an
// rt.Camera's.
#pragma once

#include <string>

#include "load/third_party.h"
#include "rt/render.pb.h"

namespace rt {

// Sets `camera`'s projection from `source` (named `name` in messages): a
// perspective camera's yfov as fov_y, an orthographic one's ymag as half of
// ortho_height. Throws std::invalid_argument naming the field that is wrong.
//
// An orthographic glTF camera gives both xmag and ymag, an aspect that need
// not be the image's: ymag wins and the width follows from the image's aspect,
// as three.js's GLTFLoader and the perspective yfov do (an image of the
// camera's own aspect shows exactly its xmag). znear and zfar are checked but
// not used: the renderer clips nothing, its rays leave from the camera's plane.
void read_gltf_projection(const tinygltf::Camera& source, const std::string& name, Camera& camera);

}  // namespace rt
