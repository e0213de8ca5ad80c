// The lights a scene without any of its own is rendered with, so that a plain
// glTF asset looks the way a viewer would show it instead of black.
#pragma once

#include "geometry/scene.h"

namespace rt {

// The default camera's view (default_camera.h) sets the rig: a key directional
// light from above, left and in front of the camera (kRigKeyLux), a weaker
// fill from the right and a little above (kRigFillLux), both with hard
// shadows, and a pale sky (kRigSky) for rays that miss unless the scene gives
// a background. The lights are appended to `scene.lights` and counted in
// `scene.rig_lights`; their positions (on the scene's bounding sphere, twice
// out, towards the light) only place them for viewers.
void add_light_rig(Scene& scene);

inline constexpr float kRigKeyLux = 2.5f;
inline constexpr float kRigFillLux = 0.8f;
inline constexpr vec3 kRigSky{0.55f, 0.62f, 0.72f};

}  // namespace rt
