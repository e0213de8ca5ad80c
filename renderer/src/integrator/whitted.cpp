#include "integrator/whitted.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <span>
#include <stdexcept>
#include <string>

#include "integrator/dielectric.h"
#include "integrator/sampling.h"
#include "geometry/normal_map.h"
#include "geometry/shadow_terminator.h"
#include "geometry/spawn.h"
#include "geometry/surface_material.h"
#include "integrator/punctual_light.h"
#include "integrator/ray_recorders.h"
#include "integrator/sphere_light.h"

namespace rt {

using namespace recorders;

namespace {

// The mirror direction about the shading normal; a bent shading normal can
// mirror below the surface, and then the true surface decides.
vec3 mirror_direction(vec3 direction, const SurfaceHit& s) {
    const vec3 mirrored = glm::reflect(direction, s.ns);
    return glm::dot(mirrored, s.ng) > 0.0f ? mirrored : glm::reflect(direction, s.ng);
}

// One of a light's samples as seen from a shaded point: the direction to it,
// the radiance it carries over its probability density, and cos theta.
struct LightSample {
    vec3 wi, weight;
    float cos_theta;
};

// What a light's `count` samples bring to one point: their shadow rays go a
// packet at a time (from one origin in nearby directions, a cone the packet
// kernels bound with one interval test per node), and each unblocked one adds
// brdf(wi) weight cos / count (visibility opacity), in sample order, as a
// ray-by-ray loop would. sample(i, ray, lit) makes sample i's shadow ray and
// LightSample (false: it has none).
template <class Recorder, class Sample, class Brdf>
vec3 light_samples_radiance(Recorder& recorder, const Accelerator& accel, uint32_t count, uint32_t depth, int parent,
                            uint32_t light, vec3 opacity, Sample&& sample, Brdf&& brdf) {
    constexpr uint32_t kPacket = Accelerator::kPacketSize;
    vec3 sum(0.0f);
    for (uint32_t first = 0; first < count; first += kPacket) {
        Ray rays[kPacket];
        LightSample lit[kPacket];
        uint32_t n = 0;
        for (uint32_t i = first; i < std::min(count, first + kPacket); ++i) n += sample(i, rays[n], lit[n]);
        float visibility[kPacket];
        int ids[kPacket];
        recorder.shadows(accel, std::span<const Ray>(rays, n), depth, parent, light, visibility, ids);
        for (uint32_t k = 0; k < n; ++k) {
            if (visibility[k] == 0.0f) continue;
            const vec3 c = brdf(lit[k].wi) * lit[k].weight * (lit[k].cos_theta / float(count)) *
                           (visibility[k] * opacity);
            recorder.contribution(ids[k], c);
            sum += c;
        }
    }
    return sum;
}

}  // namespace

vec3 phong_brdf(vec3 diffuse, vec3 specular, float shininess, vec3 n, vec3 wo, vec3 wi) {
    vec3 f = diffuse / kPi;
    if (specular != vec3(0.0f)) {
        const float cos_alpha = glm::dot(glm::reflect(-wi, n), wo);
        if (cos_alpha > 0.0f)
            f += specular * ((shininess + 2.0f) / (2.0f * kPi) * std::pow(cos_alpha, shininess));
    }
    return f;
}

WhittedIntegrator::WhittedIntegrator(const Accelerator& accel, const RenderSettings& settings)
    : accel_(accel),
      scene_(accel.scene()),
      max_depth_(settings.max_depth()),
      min_contribution_(settings.min_contribution()),
      light_samples_(settings.light_samples()),
      light_sampling_(settings.light_sampling()) {
    // The default rig is the scene's last lights: without it, fewer lights.
    light_count_ = scene_.lights.size() - (settings.light_rig() == NO_RIG ? scene_.rig_lights : 0);
    background_ = scene_.rig_lights > 0 && settings.light_rig() != NO_RIG ? scene_.rig_background : scene_.background;
    const auto* gradient = settings.has_background_gradient() ? &settings.background_gradient() : nullptr;
    if (auto given = background_from(settings.background(), gradient, "settings.background_gradient"))
        background_ = *given;
    for (size_t i = 0; i < light_count_; ++i)
        if (scene_.lights[i].radius > 0.0f) sphere_lights_.push_back(uint32_t(i));
    // The rig's fill is its last light (light_rig.h).
    rig_fill_ = scene_.rig_lights > 0 && settings.light_rig() != NO_RIG ? scene_.lights.size() - 1 : SIZE_MAX;
    const bool splits = std::any_of(scene_.materials.begin(), scene_.materials.end(),
                                    [](const Material& m) { return m.transmission != vec3(0.0f); });
    const double bound = closest_rays_bound(max_depth_, min_contribution_, splits ? 2 : 1);
    if (bound > kMaxRaysPerCameraSample) {
        char rays[32], cutoff[32];
        std::snprintf(rays, sizeof rays, "%.3g", bound);
        std::snprintf(cutoff, sizeof cutoff, "%g", double(min_contribution_));
        throw std::invalid_argument(
            "settings.max_depth: " + std::to_string(max_depth_) + " with settings.min_contribution " + cutoff +
            " lets one camera ray split into up to " + rays +
            " rays at this scene's transparent surfaces (the most allowed is " +
            std::to_string(uint64_t(kMaxRaysPerCameraSample)) + "): lower max_depth or raise min_contribution");
    }
}

double closest_rays_bound(uint32_t max_depth, float min_contribution, uint32_t branches) {
    double bound = 0.0, rays_at_depth = 1.0;
    for (uint32_t d = 0; d <= max_depth; ++d, rays_at_depth *= branches) {
        const double above_cutoff = min_contribution > 0.0f ? std::ceil(1.0 / min_contribution) - 1.0 : rays_at_depth;
        bound += std::min(rays_at_depth, above_cutoff);
    }
    return bound;
}

vec3 WhittedIntegrator::radiance(const Ray& ray, const PixelSampler& sampler, RayCounts& counts, RayCone cone) const {
    CountingRecorder recorder{counts};
    return trace(ray, cone, PRIMARY, 0, vec3(1.0f), -1, sampler, recorder);
}

vec3 WhittedIntegrator::radiance(const Ray& ray, const Hit& primary, const PixelSampler& sampler, RayCounts& counts,
                                 RayCone cone) const {
    CountingRecorder recorder{counts, &primary};
    return trace(ray, cone, PRIMARY, 0, vec3(1.0f), -1, sampler, recorder);
}

vec3 WhittedIntegrator::radiance(const Ray& ray, const PixelSampler& sampler, RayCounts& counts, AuxSample& aux,
                                 RayCone cone, bool costs, const Hit* primary) const {
    AuxRecorder recorder{counts, aux, costs, primary};
    return trace(ray, cone, PRIMARY, 0, vec3(1.0f), -1, sampler, recorder);
}

vec3 WhittedIntegrator::radiance(const Ray& ray, const PixelSampler& sampler, DebugPath& path, RayCone cone) const {
    const Bounds3 bounds = scene_.bounds();
    const float extent = bounds.empty() ? 1.0f : glm::length(bounds.extent());
    const float reach = bounds.empty() ? 1.0f : glm::length(bounds.center() - ray.origin);
    DebugRecorder recorder{path, reach + extent};
    const vec3 color = trace(ray, cone, PRIMARY, 0, vec3(1.0f), -1, sampler, recorder);
    set_vec3(path.mutable_color(), color);
    return color;
}

// Lights are few and not in the BVH: they cast no shadows, and a shadow ray
// ends on its light without the BVH having to skip it.
int WhittedIntegrator::nearest_light(const Ray& ray, float& t) const {
    int nearest = -1;
    Ray probe = ray;
    for (uint32_t index : sphere_lights_) {
        const Light& light = scene_.lights[index];
        float t_light = 0.0f;
        if (intersect_sphere(probe, Sphere{light.position, light.radius, 0}, t_light)) {
            probe.t_max = t = t_light;
            nearest = int(index);
        }
    }
    return nearest;
}

template <class Recorder>
vec3 WhittedIntegrator::trace(const Ray& ray, RayCone cone, RayKind kind, uint32_t depth, vec3 weight, int parent,
                              const PixelSampler& sampler, Recorder& recorder) const {
    Hit hit;
    const int segment = recorder.closest(accel_, ray, kind, depth, parent, weight, hit);
    if (!sphere_lights_.empty()) {
        float t = 0.0f;
        const int index = nearest_light(Ray{ray.origin, ray.direction, hit.t}, t);
        if (index >= 0) {
            const Light& light = scene_.lights[size_t(index)];
            const vec3 emitted = sphere_light_radiance(light);
            recorder.light(segment, ray, t, light, emitted);
            return emitted;
        }
    }
    if (!hit.found()) return background_(ray.direction);

    TriangleCorners corners;
    SurfaceHit s = surface_at(scene_, ray, hit, &corners);
    s.cone_width = cone.width_at(hit.t);
    s.cone_spread = cone.spread;
    s.cos_incidence = std::max(std::abs(glm::dot(ray.direction, s.ng)), 1e-6f);
    // Inside or outside is the authored normals' side (as face_viewer orients
    // them before it turns both towards the viewer and forgets it).
    const vec3 outward = glm::dot(s.ns, s.ng) < 0.0f ? -s.ng : s.ng;
    const bool entering = glm::dot(outward, ray.direction) < 0.0f;
    const vec3 wo = -ray.direction;
    const vec3 authored = s.ns;
    face_viewer(s, wo);
    const Material& m = scene_.materials[s.material];
    if (m.normal_texture) apply_normal_map(scene_, m, hit, authored, wo, s);
    const SurfaceMaterial sm = surface_material(scene_, m, s);
    recorder.surface(segment, s, hit, m, sm);

    // Light that passes the dielectric interface never reaches the Phong
    // surface; an opaque material's opacity of exactly 1 leaves it unchanged.
    // Emission is the surface's own and shows through any layer. Shadow rays
    // start where the vertex normals put the surface (shadow_terminator.h).
    SurfaceHit lit = s;
    const ShadowOrigin origin = shadow_terminator_origin(scene_, hit, s, entering ? 1.0f : -1.0f, &corners);
    lit.p = origin.p;
    lit.p_error = origin.p_error;
    vec3 color = sm.emission +
                 direct_light(lit, wo, sm, vec3(1.0f) - m.transmission, depth, segment, sampler, recorder);
    recorder.contribution(segment, color);

    // The mirror belongs to the Phong surface, which the light that passes the
    // interface never meets either. The weights of the rays a hit spawns then
    // add up to at most 1, so min_contribution bounds a camera ray's tree of
    // rays; with Kr + T above 1 it would double at every glass hit.
    vec3 mirror = sm.reflectance * (vec3(1.0f) - m.transmission);
    if (sm.coverage < 1.0f) return blended(ray, s, entering, wo, m, sm, color, mirror, depth, weight, segment,
                                           sampler, recorder);
    if (m.transmission != vec3(0.0f))
        color += transmitted(s, entering, wo, m, mirror, depth, weight, segment, sampler, recorder);
    return color + follow(s, mirror_direction(ray.direction, s), REFLECTION, mirror, depth, weight, segment, sampler,
                          recorder);
}

// A BLEND surface of coverage c: c of what an opaque one would send back, and
// 1 - c of what lies straight behind it, traced as an unbent refraction ray.
// Every weight shrinks by c first, so min_contribution still bounds the tree.
template <class Recorder>
vec3 WhittedIntegrator::blended(const Ray& ray, const SurfaceHit& s, bool entering, vec3 wo, const Material& m,
                                const SurfaceMaterial& sm, vec3 color, vec3 mirror, uint32_t depth, vec3 weight,
                                int segment, const PixelSampler& sampler, Recorder& recorder) const {
    const float c = sm.coverage;
    color *= c;
    mirror *= c;
    if (m.transmission != vec3(0.0f)) {
        vec3 fresnel(0.0f);  // the interface's reflected share, to be scaled by c too
        color += c * transmitted(s, entering, wo, m, fresnel, depth, weight * c, segment, sampler, recorder);
        mirror += c * fresnel;
    }
    color += follow(s, mirror_direction(ray.direction, s), REFLECTION, mirror, depth, weight, segment, sampler,
                    recorder);
    return color + follow(s, ray.direction, REFRACTION, vec3(1.0f - c), depth, weight, segment, sampler, recorder);
}

template <class Recorder>
vec3 WhittedIntegrator::follow(const SurfaceHit& s, vec3 direction, RayKind kind, vec3 local_weight, uint32_t depth,
                               vec3 weight, int parent, const PixelSampler& sampler, Recorder& recorder) const {
    // Follow only while the light can still show in the pixel: the product of
    // weights along the path, not just this surface's (the 2020 report's 3.3).
    const vec3 path_weight = weight * local_weight;
    if (depth >= max_depth_ || !(max_component(path_weight) > min_contribution_)) return vec3(0.0f);
    // spawn_ray offsets to the side `direction` leaves on: through the surface
    // for a refracted ray.
    const Ray ray = spawn_ray(s.p, s.p_error, s.ng, direction, s.time);
    // The flat-mirror cone (ray_cone.h): as wide as the ray's was here, as open.
    const RayCone cone{s.cone_width, s.cone_spread};
    return local_weight * trace(ray, cone, kind, depth + 1, path_weight, parent, sampler.bounce(depth + 1), recorder);
}

template <class Recorder>
vec3 WhittedIntegrator::transmitted(const SurfaceHit& s, bool entering, vec3 wo, const Material& m, vec3& mirror,
                                    uint32_t depth, vec3 weight, int parent, const PixelSampler& sampler,
                                    Recorder& recorder) const {
    // Both normals face the viewer, so eta is taken relative to the side the
    // ray comes from. Media are not tracked: a surface inside glass still sees
    // air on its outside. Radiance is not scaled by 1/eta^2 across the
    // interface (Whitted's model; it cancels for a closed object anyway).
    const float eta = entering ? m.ior : 1.0f / m.ior;
    vec3 n = s.ns;
    vec3 direction(0.0f);
    bool refracted = refract(wo, n, eta, direction);
    // A bent shading normal can refract to the viewer's side of the true
    // surface: then the true surface decides.
    if (refracted && glm::dot(direction, s.ng) >= 0.0f) {
        n = s.ng;
        refracted = refract(wo, n, eta, direction);
    }
    if (!refracted) {  // total internal reflection: all of the transmitted share reflects
        mirror += m.transmission;
        return vec3(0.0f);
    }
    const float reflectance = fr_dielectric(glm::dot(wo, n), eta);
    mirror += reflectance * m.transmission;
    return follow(s, direction, REFRACTION, (1.0f - reflectance) * m.transmission, depth, weight, parent, sampler,
                  recorder);
}

template <class Recorder>
vec3 WhittedIntegrator::direct_light(const SurfaceHit& s, vec3 wo, const SurfaceMaterial& m, vec3 opacity,
                                     uint32_t depth, int parent, const PixelSampler& sampler,
                                     Recorder& recorder) const {
    // Shadow rays stay opaque: a transmissive occluder blocks the light, as in
    // Whitted's model (caustics through glass are beyond it). A light lights
    // the point when it is above both the (possibly bent) shading normal and
    // the smooth surface the vertex normals describe, not the flat facet:
    // near a low-poly mesh's terminator the facet already faces away where
    // the smooth surface is lit, and its shadow rays start on the smooth
    // surface (shadow_terminator.h). A normal map cannot light what lies below.
    const auto brdf = [&](vec3 wi) { return phong_brdf(m.diffuse, m.specular, m.shininess, s.ns, wo, wi); };
    vec3 color(0.0f);
    for (size_t light_index = 0; light_index < light_count_; ++light_index) {
        const Light& light = scene_.lights[light_index];
        if (light.kind == DIRECTIONAL) {
            // The occlusion map darkens the rig's fill, the stand-in for ambient light, and nothing else.
            const vec3 scale = light_index == rig_fill_ ? opacity * m.occlusion : opacity;
            color += sun_light(s, wo, m, scale, uint32_t(light_index), depth, parent, sampler, recorder);
            continue;
        }
        const vec3 to_light = light.position - s.p;
        const float distance_squared = glm::dot(to_light, to_light);
        const float radius_squared = light.radius * light.radius;
        if (!(distance_squared > radius_squared)) continue;  // inside a spherical light

        if (light.radius == 0.0f) {
            const vec3 wi = to_light / std::sqrt(distance_squared);
            const float cos_theta = glm::dot(s.ns, wi);
            if (cos_theta <= 0.0f || glm::dot(s.n_smooth, wi) <= 0.0f) continue;
            // A spot's cone and a range window; exactly 1 (the same image) for a plain point light.
            const float attenuation = light.plain_point() ? 1.0f : punctual_attenuation(light, wi, distance_squared);
            if (!(attenuation > 0.0f)) continue;
            float visibility = 0.0f;
            const int shadow = recorder.shadow(accel_, spawn_ray_to(s.p, s.p_error, s.ng, light.position, s.time),
                                               depth, parent, uint32_t(light_index), visibility);
            if (visibility == 0.0f) continue;
            // Intensity first: cos / d^2 alone overflows for lights closer than
            // 1e-19, where the irradiance of a light scaled with its scene does not.
            const vec3 c =
                brdf(wi) * (light.intensity * (attenuation * cos_theta) / distance_squared) * (visibility * opacity);
            recorder.contribution(shadow, c);
            color += c;
            continue;
        }

        // A spherical light: light_samples points on it, each pixel sample
        // taking its own share of the light's sample dimension.
        const SphereLightSampler light_sampler(light, light_sampling_, s.p);
        color += light_samples_radiance(
            recorder, accel_, light_samples_, depth, parent, uint32_t(light_index), opacity,
            [&](uint32_t i, Ray& ray, LightSample& lit) {
                SphereLightSample sample;
                const vec2 u = sampler.get_2d(uint32_t(light_index), i, light_samples_);
                if (!light_sampler.sample(u, sample)) return false;
                const float cos_theta = glm::dot(s.ns, sample.wi);
                if (cos_theta <= 0.0f || glm::dot(s.n_smooth, sample.wi) <= 0.0f) return false;
                ray = spawn_ray_to(s.p, s.p_error, s.ng, sample.point, s.time);
                lit = {sample.wi, sample.weight, cos_theta};
                return true;
            },
            brdf);
    }
    return color;
}

// A directional light: one shadow ray to infinity against its direction, or
// with an angular diameter light_samples of them spread over its cone, drawn
// from the light's own sample dimension like a spherical light's.
template <class Recorder>
vec3 WhittedIntegrator::sun_light(const SurfaceHit& s, vec3 wo, const SurfaceMaterial& m, vec3 opacity,
                                  uint32_t light_index, uint32_t depth, int parent, const PixelSampler& sampler,
                                  Recorder& recorder) const {
    const Light& light = scene_.lights[light_index];
    const bool soft = light.angular_diameter > 0.0f;
    const uint32_t count = soft ? light_samples_ : 1;
    const SunSampler sun(light);
    return light_samples_radiance(
        recorder, accel_, count, depth, parent, light_index, opacity,
        [&](uint32_t i, Ray& ray, LightSample& lit) {
            const vec3 wi = soft ? sun.sample(sampler.get_2d(light_index, i, count)) : -light.direction;
            const float cos_theta = glm::dot(s.ns, wi);
            if (cos_theta <= 0.0f || glm::dot(s.n_smooth, wi) <= 0.0f) return false;
            ray = spawn_ray(s.p, s.p_error, s.ng, wi, s.time);
            lit = {wi, light.intensity, cos_theta};
            return true;
        },
        [&](vec3 wi) { return phong_brdf(m.diffuse, m.specular, m.shininess, s.ns, wo, wi); });
}

}  // namespace rt
