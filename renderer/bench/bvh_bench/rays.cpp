#include "rays.h"

#include <algorithm>
#include <cmath>

#include "geometry/spawn.h"
#include "geometry/surface.h"
#include "integrator/camera.h"
#include "integrator/default_camera.h"
#include "integrator/sampling.h"
#include "timing.h"

namespace rt::bench {
namespace {

// Keys of the sample hashes: one stream per ray kind, so that adding a kind
// never changes another's rays.
constexpr uint32_t kRandomSeed = 0x52414e44u;   // "RAND"
constexpr uint32_t kDiffuseSeed = 0x44494646u;  // "DIFF"
constexpr uint32_t kSoftSeed = 0x534f4654u;     // "SOFT"

float sample(uint32_t seed, uint32_t index, uint32_t dimension) {
    return unit_float(hash_combine(hash_combine(seed, index), dimension));
}

vec3 uniform_sphere(float u1, float u2) {
    const float z = 1.0f - 2.0f * u1;
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    const float phi = 2.0f * kPi * u2;
    return {r * std::cos(phi), r * std::sin(phi), z};
}

// Malley's method: a uniform point on the disc lifted onto the hemisphere about n.
vec3 cosine_hemisphere(vec3 n, float u1, float u2) {
    const float r = std::sqrt(u1);
    const float phi = 2.0f * kPi * u2;
    vec3 b1, b2;
    orthonormal_basis(n, b1, b2);
    const vec3 w = r * std::cos(phi) * b1 + r * std::sin(phi) * b2 + std::sqrt(std::max(0.0f, 1.0f - u1)) * n;
    return glm::normalize(w);
}

void add_camera_rays(const Scene& scene, uint32_t size, RaySet& rays) {
    const ViewCamera camera(default_camera(scene), size, size);
    const uint32_t blocks = (size + kPacketSide - 1) / kPacketSide;
    for (uint32_t by = 0; by < blocks; ++by)
        for (uint32_t bx = 0; bx < blocks; ++bx) {
            Packet packet;
            packet.fill(kInactiveLane);
            for (uint32_t ly = 0; ly < kPacketSide; ++ly)
                for (uint32_t lx = 0; lx < kPacketSide; ++lx) {
                    const uint32_t x = bx * kPacketSide + lx, y = by * kPacketSide + ly;
                    if (x >= size || y >= size) continue;
                    packet[ly * kPacketSide + lx] = uint32_t(rays.primary.size());
                    rays.primary.push_back(camera.generate_ray(x + 0.5f, y + 0.5f));
                }
            rays.primary_packets.push_back(packet);
        }
}

// Shadow and diffuse rays leave a primary hit the way the integrator's do:
// spawned off the surface by its rounding-error bound (geometry/spawn.h).
void add_secondary_rays(const Scene& scene, const Accelerator& accel, unsigned threads, RaySet& rays) {
    std::vector<Hit> hits(rays.primary.size());
    parallel_for(hits.size(), threads, [&](size_t i) { accel.intersect(rays.primary[i], hits[i]); });

    const Bounds3 bounds = scene.bounds();
    const vec3 light = !scene.lights.empty()
                           ? scene.lights.front().position
                           : vec3(bounds.center().x, bounds.max.y + bounds.extent().y, bounds.center().z);
    std::vector<uint32_t> shadow_of(rays.primary.size(), kInactiveLane);
    for (size_t i = 0; i < hits.size(); ++i) {
        if (!hits[i].found()) continue;
        const Ray& ray = rays.primary[i];
        SurfaceHit s = surface_at(scene, ray, hits[i]);
        shadow_of[i] = uint32_t(rays.shadow.size());
        rays.shadow.push_back(spawn_ray_to(s.p, s.p_error, s.ng, light, s.time));
        face_viewer(s, -ray.direction);
        const vec3 w = cosine_hemisphere(s.ns, sample(kDiffuseSeed, uint32_t(i), 0), sample(kDiffuseSeed, uint32_t(i), 1));
        rays.diffuse.push_back(spawn_ray(s.p, s.p_error, s.ng, w, s.time));
    }
    for (const Packet& primary : rays.primary_packets) {
        Packet packet;
        for (uint32_t lane = 0; lane < kPacketWidth; ++lane)
            packet[lane] = primary[lane] == kInactiveLane ? kInactiveLane : shadow_of[primary[lane]];
        rays.shadow_packets.push_back(packet);
    }
    const float radius = !scene.lights.empty() && scene.lights.front().radius > 0.0f
                             ? scene.lights.front().radius
                             : 0.02f * std::max({bounds.extent().x, bounds.extent().y, bounds.extent().z});
    for (size_t i = 0; i < hits.size(); i += kPacketWidth) {
        if (!hits[i].found()) continue;
        const SurfaceHit s = surface_at(scene, rays.primary[i], hits[i]);
        Packet packet;
        for (uint32_t lane = 0; lane < kPacketWidth; ++lane) {
            const uint32_t key = uint32_t(i) * kPacketWidth + lane;
            const vec3 point = light + radius * uniform_sphere(sample(kSoftSeed, key, 0), sample(kSoftSeed, key, 1));
            packet[lane] = uint32_t(rays.soft_shadow.size());
            rays.soft_shadow.push_back(spawn_ray_to(s.p, s.p_error, s.ng, point, s.time));
        }
        rays.soft_shadow_packets.push_back(packet);
    }
}

void add_random_rays(const Scene& scene, size_t count, RaySet& rays) {
    Bounds3 box = scene.bounds();
    // Plus 1 % of the largest extent on every axis, so a flat scene's box still has depth.
    const vec3 extent = box.extent();
    const vec3 margin = 0.1f * extent + vec3(0.01f * std::max({extent.x, extent.y, extent.z, 1e-3f}));
    box.min -= margin;
    box.max += margin;
    for (uint32_t i = 0; i < count; ++i) {
        const vec3 u(sample(kRandomSeed, i, 0), sample(kRandomSeed, i, 1), sample(kRandomSeed, i, 2));
        const vec3 origin = box.min + u * (box.max - box.min);
        rays.random.push_back(Ray{origin, uniform_sphere(sample(kRandomSeed, i, 3), sample(kRandomSeed, i, 4)),
                                  kInfinity, 0.0f});
    }
}

}  // namespace

RaySet make_rays(const Scene& scene, const Accelerator& accel, uint32_t size, size_t random_count,
                 unsigned threads) {
    RaySet rays;
    add_camera_rays(scene, size, rays);
    add_secondary_rays(scene, accel, threads, rays);
    add_random_rays(scene, random_count, rays);
    return rays;
}

}  // namespace rt::bench
