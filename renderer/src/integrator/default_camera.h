// The camera a render uses when the user names none and the scene has none.
#pragma once

#include "rt/render.pb.h"
#include "geometry/scene.h"

namespace rt {

// The scene's first camera, or one in front of the scene (+Z) that frames its
// bounding sphere with a 45 degree vertical field of view.
Camera default_camera(const Scene& scene);

}  // namespace rt
