// The pinhole camera of the 2020 report: a look-at frame and a vertical
// field of view; the horizontal one follows from the image's aspect ratio.
// Given a pose at shutter close, it moves while the shutter is open: position,
// target and up travel in straight lines, and each ray's frame is built from
// the pose at the ray's time, exactly as a still camera at that pose builds its
// own.
#pragma once

#include <cstdint>
#include <string>

#include "integrator/ray_cone.h"
#include "util/math.h"
#include "util/ray.h"
#include "rt/render.pb.h"

namespace rt {

class PinholeCamera {
  public:
    // Throws std::invalid_argument when a pose has no direction (position ==
    // target) or its up vector is parallel to the view direction, at either
    // end of the shutter interval (naming camera.shutter_close) or in between.
    PinholeCamera(const Camera& camera, uint32_t width, uint32_t height);

    bool moving() const { return moving_; }

    // A unit-direction ray through the film point (px, py) in pixel units: (0, 0)
    // is the top-left corner of the image, (width, height) the bottom-right. It
    // leaves at shutter time `time` in [0, 1], which a still camera only passes on.
    Ray generate_ray(float px, float py, float time = 0.0f) const;

    // The ray cone of every ray generate_ray() makes: one pixel's angle.
    RayCone ray_cone() const { return RayCone::camera(tan_y_, 1.0f / inv_height_); }

  private:
    struct Pose {
        vec3 position;
        vec3 target;
        vec3 up;
    };
    struct Frame {
        vec3 position;
        vec3 forward;
        vec3 right;  // scaled by tan(fov_x / 2)
        vec3 up;     // scaled by tan(fov_y / 2)
    };
    // Throws naming `what` (and `when`, if given) unless `pose` has a frame.
    static void check(const Pose& pose, const std::string& what, const std::string& when = "");
    Pose pose_at(float time) const;
    Frame frame(const Pose& pose) const;
    Ray ray_through(const Frame& frame, float px, float py, float time) const;

    float tan_x_;
    float tan_y_;
    float inv_width_;
    float inv_height_;
    bool moving_ = false;
    Pose open_;
    Pose close_;
    Frame still_;  // the frame at shutter open, all a still camera needs
};

}  // namespace rt
