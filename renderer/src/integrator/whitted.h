// The Whitted integrator of the 2020 report: Phong shading from every light
// with shadow rays (sections 2, 4, 5), plus recursive mirror reflection (section
// 3) and refraction through smooth dielectrics (docs/materials.md), both cut off
// when the path weight can no longer change the pixel. Point, spot and
// directional lights (punctual_light.h) take one shadow ray each; spherical
// lights and suns of some angular diameter light_samples. Spherical lights are
// also seen: a camera, reflection or refraction ray that meets one returns its
// radiance.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/accel.h"
#include "image/aov.h"
#include "util/ray.h"
#include "rt/debug.pb.h"
#include "rt/render.pb.h"
#include "integrator/ray_cone.h"
#include "integrator/sampler.h"
#include "geometry/surface.h"
#include "geometry/surface_material.h"

namespace rt {

struct RayCounts {
    uint64_t camera = 0;
    uint64_t reflection = 0;
    uint64_t shadow = 0;
    uint64_t refraction = 0;

    uint64_t total() const { return camera + reflection + shadow + refraction; }
    RayCounts& operator+=(const RayCounts& o) {
        camera += o.camera;
        reflection += o.reflection;
        shadow += o.shadow;
        refraction += o.refraction;
        return *this;
    }
};

// The most closest-hit rays (camera, reflection, refraction) one camera sample
// can trace when each hit spawns at most `branches` of them (1 on mirrors, 2 on
// glass: a reflection and a refraction). Depth d holds at most branches^d, and
// fewer than 1 / min_contribution whose path weight is above it, because the
// weights of the rays a hit spawns add up to at most 1 (for grey materials;
// with coloured ones each channel's do, which allows up to three times as many).
double closest_rays_bound(uint32_t max_depth, float min_contribution, uint32_t branches);

// The most closest_rays_bound() a render may allow: about a second per camera
// sample. Glass at max_depth 64 with the default cutoff allows some 56,000;
// without a cutoff, 2^65.
inline constexpr double kMaxRaysPerCameraSample = double(1 << 20);

class WhittedIntegrator {
  public:
    // `settings` must have had its limits applied (proto_limits.h). Throws
    // std::invalid_argument naming max_depth and min_contribution when they let
    // a camera ray split into more than kMaxRaysPerCameraSample rays through
    // the scene's transmissive materials: a render that would never end.
    WhittedIntegrator(const Accelerator& accel, const RenderSettings& settings);

    // Linear RGB carried back along a camera ray. `sampler` gives the pixel
    // sample's light samples, so the result is the same whichever thread
    // computes it. `cone` is the ray's footprint (ray_cone.h), which filters
    // textures; without one they are read unfiltered (mip level 0).
    vec3 radiance(const Ray& ray, const PixelSampler& sampler, RayCounts& counts, RayCone cone = {}) const;
    // The same when a packet query (Accelerator::intersect over a span) has
    // found the camera ray's hit already.
    vec3 radiance(const Ray& ray, const Hit& primary, const PixelSampler& sampler, RayCounts& counts,
                  RayCone cone = {}) const;

    // The same, also reporting the primary hit's depth, the albedo and normal
    // of the surface the pixel shows (past mirrors and glass) and, with
    // `costs`, the BVH traversal cost of every ray traced (aov.h). `primary`:
    // the camera ray's hit when a packet found it (costs false only).
    vec3 radiance(const Ray& ray, const PixelSampler& sampler, RayCounts& counts, AuxSample& aux,
                  RayCone cone = {}, bool costs = true, const Hit* primary = nullptr) const;

    // The same, recording every ray it traces into `path` for the debugger.
    vec3 radiance(const Ray& ray, const PixelSampler& sampler, DebugPath& path, RayCone cone = {}) const;

  private:
    template <class Recorder>
    vec3 trace(const Ray& ray, RayCone cone, RayKind kind, uint32_t depth, vec3 weight, int parent,
               const PixelSampler& sampler, Recorder& recorder) const;
    // Follows a secondary ray of `kind` when its path weight can still show.
    template <class Recorder>
    vec3 follow(const SurfaceHit& s, vec3 direction, RayKind kind, vec3 local_weight, uint32_t depth, vec3 weight,
                int parent, const PixelSampler& sampler, Recorder& recorder) const;
    // The light a transmissive surface lets through: the refracted ray's
    // radiance times its weight. Adds the Fresnel-reflected share to `mirror`.
    template <class Recorder>
    vec3 transmitted(const SurfaceHit& s, bool entering, vec3 wo, const Material& m, vec3& mirror, uint32_t depth,
                     vec3 weight, int parent, const PixelSampler& sampler, Recorder& recorder) const;
    template <class Recorder>
    vec3 blended(const Ray& ray, const SurfaceHit& s, bool entering, vec3 wo, const Material& m,
                 const SurfaceMaterial& sm, vec3 color, vec3 mirror, uint32_t depth, vec3 weight, int segment,
                 const PixelSampler& sampler, Recorder& recorder) const;
    template <class Recorder>
    vec3 direct_light(const SurfaceHit& s, vec3 wo, const SurfaceMaterial& m, vec3 opacity, uint32_t depth, int parent,
                      const PixelSampler& sampler, Recorder& recorder) const;
    template <class Recorder>
    vec3 sun_light(const SurfaceHit& s, vec3 wo, const SurfaceMaterial& m, vec3 opacity, uint32_t light_index,
                   uint32_t depth, int parent, const PixelSampler& sampler, Recorder& recorder) const;
    // The nearest spherical light `ray` meets before ray.t_max, or -1; its distance in `t`.
    int nearest_light(const Ray& ray, float& t) const;

    const Accelerator& accel_;
    const Scene& scene_;
    uint32_t max_depth_;
    float min_contribution_;
    uint32_t light_samples_;
    LightSampling light_sampling_;
    size_t rig_fill_;                      // the default rig's fill light, SIZE_MAX without the rig
    size_t light_count_;                   // the lights that shine: all, or all but the default rig
    Background background_;                // what rays that miss see: the settings', else the scene's
    std::vector<uint32_t> sphere_lights_;  // indices of the lights with a radius
};

// Lafortune and Willems' normalized Phong: Kd/pi + Ks (n+2)/(2 pi) cos^n(alpha),
// alpha between the mirrored light direction and the view direction. The
// normalization keeps the lobe's energy independent of the exponent.
vec3 phong_brdf(vec3 diffuse, vec3 specular, float shininess, vec3 n, vec3 wo, vec3 wi);

}  // namespace rt
