// The pinhole camera of the origin document: a look-at frame and a vertical
// field of view; the horizontal one follows from the image's aspect ratio.
#pragma once

#include <cstdint>

#include "math.h"
#include "ray.h"
#include "rt/render.pb.h"

namespace rt {

class PinholeCamera {
  public:
    // Throws std::invalid_argument when the camera has no direction (position ==
    // target) or its up vector is parallel to the view direction.
    PinholeCamera(const Camera& camera, uint32_t width, uint32_t height);

    // A unit-direction ray through the film point (px, py) in pixel units: (0, 0)
    // is the top-left corner of the image, (width, height) the bottom-right.
    Ray generate_ray(float px, float py) const;

    vec3 position() const { return position_; }

  private:
    vec3 position_;
    vec3 forward_;
    vec3 right_;  // scaled by tan(fov_x / 2)
    vec3 up_;     // scaled by tan(fov_y / 2)
    float inv_width_;
    float inv_height_;
};

}  // namespace rt
