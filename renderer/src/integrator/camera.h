// The camera of a render: the 2020 report's pinhole (a look-at frame and a
// vertical field of view) or an orthographic camera (the same frame, and the
// height of the image in world units). Either way the horizontal extent
// follows from the image's aspect ratio. Given a pose at shutter close, it
// moves while the shutter is open: position, target and up travel in straight
// lines, and each ray's frame is built from the pose at the ray's time, exactly
// as a still camera at that pose builds its own.
#pragma once

#include <cstdint>
#include <string>

#include "integrator/ray_cone.h"
#include "util/math.h"
#include "util/ray.h"
#include "rt/render.pb.h"

namespace rt {

class ViewCamera {
  public:
    // Throws std::invalid_argument when a pose has no direction (position ==
    // target) or its up vector is parallel to the view direction, at either
    // end of the shutter interval (naming camera.shutter_close) or in between,
    // and when an orthographic camera has no ortho_height.
    ViewCamera(const Camera& camera, uint32_t width, uint32_t height);

    bool moving() const { return moving_; }
    bool orthographic() const { return orthographic_; }

    // A unit-direction ray through the film point (px, py) in pixel units: (0, 0)
    // is the top-left corner of the image, (width, height) the bottom-right. It
    // leaves at shutter time `time` in [0, 1], which a still camera only passes on.
    // A pinhole's rays leave from the eye; an orthographic camera's are parallel
    // and leave from the film point on the plane through `position` square to
    // the view, so what lies behind that plane is not seen.
    Ray generate_ray(float px, float py, float time = 0.0f) const;

    // The ray cone of every ray generate_ray() makes: one pixel's angle from
    // the eye, or for parallel rays one pixel's height and no spread.
    RayCone ray_cone() const;

  private:
    struct Pose {
        vec3 position;
        vec3 target;
        vec3 up;
    };
    struct Frame {
        vec3 position;
        vec3 forward;
        vec3 right;  // scaled by half the image's extent: tan(fov_x / 2), or half the width
        vec3 up;     // the same vertically
    };
    // Throws naming `what` (and `when`, if given) unless `pose` has a frame.
    static void check(const Pose& pose, const std::string& what, const std::string& when = "");
    Pose pose_at(float time) const;
    Frame frame(const Pose& pose) const;
    Ray ray_through(const Frame& frame, float px, float py, float time) const;

    // Half the image's extent: tangents of half the field of view for a
    // pinhole, world units on the image plane for an orthographic camera.
    float half_x_;
    float half_y_;
    float inv_width_;
    float inv_height_;
    bool orthographic_ = false;
    bool moving_ = false;
    Pose open_;
    Pose close_;
    Frame still_;  // the frame at shutter open, all a still camera needs
};

}  // namespace rt
