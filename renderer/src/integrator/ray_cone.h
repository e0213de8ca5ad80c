// Ray cones (Akenine-Möller et al., "Texture Level of Detail Strategies for
// Real-Time Ray Tracing", Ray Tracing Gems 2019, ch. 20; improved in JCGT 10(1),
// 2021): each closest-hit ray carries a cone that starts as wide as what its
// pixel sees, so a texture can be filtered over the footprint the ray stands
// for instead of aliasing into moiré far away. The cone travels beside the
// Ray, not in it: Ray is the BVH traversal's hot type, and traversal never
// needs the cone.
#pragma once

#include <cmath>
#include <cstdint>

namespace rt {

struct RayCone {
    float width = 0.0f;   // at the ray's origin, in world units
    float spread = 0.0f;  // the angle it opens by, radians; small, so width grows by spread * t

    float width_at(float t) const { return width + spread * t; }

    // A camera ray's cone: a point at the eye, opening by the angle one pixel
    // subtends at the image's centre, atan(2 tan(fov_y / 2) / height).
    // The same for every pixel and every sample of a pixel: with
    // many samples each still stands for the whole pixel, which errs towards
    // blur, never towards aliasing.
    static RayCone camera(float tan_half_fov_y, float height) {
        return {0.0f, std::atan(2.0f * tan_half_fov_y / height)};
    }

    // An orthographic camera's ray: as wide as one pixel's footprint on the
    // image plane, in world units, and just as wide at any distance.
    static RayCone parallel(float pixel_size) { return {pixel_size, 0.0f}; }

    // The cone of a ray a hit spawns (reflection, refraction, a BLEND
    // surface's straight-through ray): as wide as this one where it hit, with
    // the same spread. That treats every surface as flat; a curved mirror
    // would widen or narrow it (RTG's surface spread angle, left out).
    RayCone spawned(float t) const { return {width_at(t), spread}; }
};

}  // namespace rt
