// The measurements behind the Stability tests and bench/stability_table, so
// that the tests' limits and the charts' numbers come from the same code:
// shadow rays that go wrong, rays that leak through a closed mesh, pixels that
// are not finite, and the rays one camera sample traces.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <optional>
#include <random>
#include <utility>
#include <vector>

#include "geometry/accel.h"
#include "bvh/binned_sah_builder.h"
#include "bvh/traverse.h"
#include "integrator/camera.h"
#include "moller_trumbore.h"
#include "integrator/render.h"
#include "geometry/spawn.h"
#include "stability_scenes.h"
#include "geometry/surface.h"

namespace rt::testing {

// Where a shadow ray starts. `epsilon`: the 2020 report's way, a fixed step
// from the hit point towards the light (its section 4); none: ours,
// spawn.h's offset by the hit point's rounding-error bound. Every kind is
// traced by our accelerator, so that only the origin differs; its triangle
// test already refuses hits within the error bound of t, which spares the
// epsilons some of the failures they had in the 2020 report.
struct ShadowOrigin {
    const char* name;
    std::optional<float> epsilon;
};

inline const ShadowOrigin kShadowOrigins[] = {{"eps_1e-3", 1e-3f}, {"eps_1e-5", 1e-5f}, {"ours", std::nullopt}};

inline Ray shadow_ray(const SurfaceHit& s, vec3 light, const ShadowOrigin& origin) {
    if (!origin.epsilon) return spawn_ray_to(s.p, s.p_error, s.ng, light, s.time);
    const vec3 w = glm::normalize(light - s.p);
    const vec3 start = s.p + *origin.epsilon * w;
    return Ray{start, w, glm::length(light - start), s.time};
}

struct ShadowTally {
    uint64_t pixels = 0;  // camera rays that met a surface facing the light
    uint64_t wrong = 0;   // of those, shadow rays that disagree with the scene's construction

    double share() const { return pixels == 0 ? 0.0 : double(wrong) / double(pixels); }
    ShadowTally& operator+=(const ShadowTally& o) {
        pixels += o.pixels;
        wrong += o.wrong;
        return *this;
    }
};

// One tally per kShadowOrigins entry, from a size x size image of camera rays
// whose hits all cast a shadow ray of every kind, through the renderer's own
// accelerator and surface code.
inline std::vector<ShadowTally> tally_shadow_rays(const ShadowScene& shadow, uint32_t size) {
    const Accelerator accel(shadow.scene, 1);
    const ViewCamera camera(shadow.camera, size, size);
    std::vector<ShadowTally> tallies(std::size(kShadowOrigins));
    for (uint32_t y = 0; y < size; ++y) {
        for (uint32_t x = 0; x < size; ++x) {
            const Ray ray = camera.generate_ray(float(x) + 0.5f, float(y) + 0.5f);
            Hit hit;
            if (!accel.intersect(ray, hit)) continue;
            SurfaceHit s = surface_at(shadow.scene, ray, hit);
            face_viewer(s, -ray.direction);
            // The integrator casts no shadow ray from a surface facing away.
            if (!(glm::dot(s.ng, shadow.light - s.p) > 0.0f)) continue;
            for (size_t m = 0; m < tallies.size(); ++m) {
                ++tallies[m].pixels;
                tallies[m].wrong += accel.occluded(shadow_ray(s, shadow.light, kShadowOrigins[m])) == shadow.lit;
            }
        }
    }
    return tallies;
}

// The faces around each vertex and each edge of a mesh, and their outward normals.
struct MeshFeatures {
    std::vector<vec3> face_normals;  // outward: on the side of the vertex normals
    std::vector<std::vector<uint32_t>> vertex_faces;
    struct Edge {
        uint32_t a, b;
        std::vector<uint32_t> faces;
    };
    std::vector<Edge> edges;

    explicit MeshFeatures(const Scene& mesh) : vertex_faces(mesh.positions.size()) {
        std::map<std::pair<uint32_t, uint32_t>, std::vector<uint32_t>> edge_faces;
        for (uint32_t f = 0; f < mesh.triangles.size(); ++f) {
            const uvec3 t = mesh.triangles[f];
            const vec3 p0 = mesh.positions[t.x], p1 = mesh.positions[t.y], p2 = mesh.positions[t.z];
            const vec3 n = glm::normalize(glm::cross(p1 - p0, p2 - p0));
            const vec3 outward = mesh.normals[t.x] + mesh.normals[t.y] + mesh.normals[t.z];
            face_normals.push_back(glm::dot(n, outward) < 0.0f ? -n : n);
            for (int k = 0; k < 3; ++k) {
                vertex_faces[t[k]].push_back(f);
                const uint32_t a = t[k], b = t[(k + 1) % 3];
                edge_faces[{std::min(a, b), std::max(a, b)}].push_back(f);
            }
        }
        for (auto& [ends, faces] : edge_faces) edges.push_back({ends.first, ends.second, std::move(faces)});
    }
};

// A direction on the outer side of every face around a point, more than 17
// degrees off each (its cosine with each normal above 0.3), else their mean
// normal: a ray along it crosses the surface there, so that missing the
// surface is a leak, never a graze.
inline vec3 crossing_direction(const std::vector<vec3>& normals, std::mt19937& rng) {
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    vec3 mean(0.0f);
    for (vec3 n : normals) mean += n;
    mean = glm::normalize(mean);
    for (int attempt = 0; attempt < 64; ++attempt) {
        const vec3 w = glm::normalize(mean + 0.7f * vec3(unit(rng), unit(rng), unit(rng)));
        if (std::all_of(normals.begin(), normals.end(), [&](vec3 n) { return glm::dot(w, n) > 0.3f; })) return w;
    }
    return mean;
}

// `count` rays aimed exactly at the edges and vertices of a closed mesh, half
// at each: an edge point is the lerp of its two vertices in float, as a user's
// code would compute it. Half come from well outside, half from just inside,
// and each ends just past its point: one that meets nothing on the way there
// has leaked through the surface.
inline std::vector<Ray> edge_and_vertex_rays(const Scene& mesh, size_t count, uint32_t seed) {
    const MeshFeatures features(mesh);
    const float size = glm::length(mesh.bounds().extent());
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::vector<Ray> rays;
    rays.reserve(count);
    for (size_t i = 0; i < count; ++i) {
        const bool at_vertex = (i / 2) % 2 == 1;
        const bool from_inside = i % 2 == 1;
        std::vector<vec3> normals;
        vec3 target;
        if (at_vertex) {
            const size_t v = std::uniform_int_distribution<size_t>(0, mesh.positions.size() - 1)(rng);
            target = mesh.positions[v];
            for (uint32_t f : features.vertex_faces[v]) normals.push_back(features.face_normals[f]);
        } else {
            const MeshFeatures::Edge& edge =
                features.edges[std::uniform_int_distribution<size_t>(0, features.edges.size() - 1)(rng)];
            const vec3 a = mesh.positions[edge.a], b = mesh.positions[edge.b];
            target = a + unit(rng) * (b - a);
            for (uint32_t f : edge.faces) normals.push_back(features.face_normals[f]);
        }
        const vec3 w = crossing_direction(normals, rng);
        const vec3 origin = from_inside ? target - 1e-3f * size * w : target + 2.0f * size * w;
        const float distance = glm::length(target - origin);
        rays.push_back(Ray{origin, (target - origin) / distance, distance * 1.001f});
    }
    return rays;
}

// Rays that meet nothing before their t_max: the watertight test through the
// accelerator, as the renderer traces shadow rays.
inline uint64_t watertight_leaks(const Accelerator& accel, const std::vector<Ray>& rays) {
    uint64_t leaks = 0;
    for (const Ray& ray : rays) leaks += !accel.occluded(ray);
    return leaks;
}

// The same with the 2020 report's method: the Möller-Trumbore test in a binary
// BVH over the accelerator's scene.
inline uint64_t moller_trumbore_leaks(const Accelerator& accel, const std::vector<Ray>& rays) {
    const Scene& scene = accel.scene();
    std::vector<Bounds3> bounds(scene.triangles.size());
    std::vector<vec3> centroids(scene.triangles.size());
    for (size_t i = 0; i < bounds.size(); ++i) {
        for (int k = 0; k < 3; ++k) bounds[i].extend(scene.positions[scene.triangles[i][k]]);
        centroids[i] = bounds[i].center();
    }
    const bvh::Bvh bvh = bvh::build_binned_sah(bounds, centroids);
    uint64_t leaks = 0;
    for (const Ray& ray : rays) {
        const auto leaf_test = [&](uint32_t first, uint32_t count, float& t_max) {
            for (uint32_t i = first; i < first + count; ++i) {
                const uvec3 t = scene.triangles[bvh.prim_ids[i]];
                float t_hit;
                if (moller_trumbore(ray, scene.positions[t.x], scene.positions[t.y], scene.positions[t.z], t_max,
                                    t_hit))
                    return true;
            }
            return false;
        };
        leaks += !bvh::traverse<bvh::Query::any_hit>(bvh, ray, leaf_test);
    }
    return leaks;
}

// Pixels of a whole render with any channel NaN or infinite.
inline uint64_t non_finite_pixels(const Scene& scene, const Camera& camera, const RenderSettings& settings,
                                  unsigned threads = 0) {
    const Accelerator accel(scene, threads);
    const Renderer renderer(accel, settings, camera);
    RenderStats stats;
    const Image image = renderer.render(threads, 16, nullptr, stats);
    uint64_t count = 0;
    for (uint32_t y = 0; y < image.height; ++y)
        for (uint32_t x = 0; x < image.width; ++x) count += !is_finite(image.pixel(x, y));
    return count;
}

// The most rays of each kind a pixel traced per camera sample (with one sample
// per pixel, the most one camera ray's tree held), and the time for all pixels.
struct DepthRun {
    uint64_t most_closest_rays = 0;
    uint64_t most_shadow_rays = 0;
    double seconds = 0.0;
};

// Renders every pixel of `settings`' image on its own, on one thread, to count
// its rays.
inline DepthRun trace_depth(const Scene& scene, const Camera& camera, const RenderSettings& settings) {
    const Accelerator accel(scene, 1);
    const Renderer renderer(accel, settings, camera);
    DepthRun run;
    const auto start = std::chrono::steady_clock::now();
    for (uint32_t y = 0; y < renderer.settings().height(); ++y) {
        for (uint32_t x = 0; x < renderer.settings().width(); ++x) {
            float rgb[3];
            const RenderStats stats = renderer.render_tile({x, y, 1, 1}, rgb);
            const RayCounts& rays = stats.rays;
            run.most_closest_rays = std::max<uint64_t>(run.most_closest_rays,
                                                       (rays.camera + rays.reflection + rays.refraction) / stats.samples);
            run.most_shadow_rays = std::max<uint64_t>(run.most_shadow_rays, rays.shadow / stats.samples);
        }
    }
    run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return run;
}

}  // namespace rt::testing
