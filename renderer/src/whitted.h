// The Whitted integrator of the origin document: Phong shading from every light
// with shadow rays (sections 2, 4, 5), plus recursive mirror reflection (section
// 3) cut off when the path weight can no longer change the pixel.
#pragma once

#include <cstdint>

#include "accel.h"
#include "aov.h"
#include "ray.h"
#include "rt/debug.pb.h"
#include "rt/render.pb.h"
#include "surface.h"

namespace rt {

struct RayCounts {
    uint64_t camera = 0;
    uint64_t reflection = 0;
    uint64_t shadow = 0;

    uint64_t total() const { return camera + reflection + shadow; }
    RayCounts& operator+=(const RayCounts& o) {
        camera += o.camera;
        reflection += o.reflection;
        shadow += o.shadow;
        return *this;
    }
};

class WhittedIntegrator {
  public:
    // `settings` must have had its limits applied (proto_limits.h).
    WhittedIntegrator(const Accelerator& accel, const RenderSettings& settings);

    // Linear RGB carried back along a camera ray. `pixel_key` seeds the pixel's
    // light samples, so the result is the same whichever thread computes it.
    vec3 radiance(const Ray& ray, uint32_t pixel_key, RayCounts& counts) const;

    // The same, also reporting the primary hit's depth, normal and albedo and
    // the BVH traversal cost of every ray traced (aov.h).
    vec3 radiance(const Ray& ray, uint32_t pixel_key, RayCounts& counts, AuxSample& aux) const;

    // The same, recording every ray it traces into `path` for the debugger.
    vec3 radiance(const Ray& ray, uint32_t pixel_key, DebugPath& path) const;

  private:
    template <class Recorder>
    vec3 trace(const Ray& ray, uint32_t depth, vec3 weight, int parent, uint32_t pixel_key,
               Recorder& recorder) const;
    template <class Recorder>
    vec3 direct_light(const SurfaceHit& s, vec3 wo, const Material& m, vec3 diffuse, uint32_t depth,
                      int parent, uint32_t pixel_key, Recorder& recorder) const;

    const Accelerator& accel_;
    const Scene& scene_;
    uint32_t max_depth_;
    float min_contribution_;
    uint32_t light_samples_;
};

// Lafortune and Willems' normalized Phong: Kd/pi + Ks (n+2)/(2 pi) cos^n(alpha),
// alpha between the mirrored light direction and the view direction. The
// normalization keeps the lobe's energy independent of the exponent.
vec3 phong_brdf(vec3 diffuse, vec3 specular, float shininess, vec3 n, vec3 wo, vec3 wi);

}  // namespace rt
