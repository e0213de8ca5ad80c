#include "geometry/accel.h"

#include <chrono>

#include "bvh/binned_sah_builder.h"
#include "bvh/traverse.h"
#include "geometry/surface_material.h"
#include "geometry/triangle.h"

namespace rt {
namespace {

// SAH cost of a traversal step (both children's boxes) relative to one
// watertight triangle test: the value that traced the full dragon fastest in
// bench/bvh_bench.cpp (1 and 3 were within a few percent).
constexpr float kTraversalCost = 2.0f;

// What a traversal did, for the debugger and the BVH-cost output: counted, or
// recorded node by node.
// The plain queries' observer does nothing and compiles away.
struct CountingObserver {
    TraversalStats& stats;
    void visit_node(uint32_t) { ++stats.nodes_visited; }
    void test_triangles(uint32_t count) { stats.triangles_tested += count; }
};

struct RecordingObserver {
    TraversalRecord& record;
    void visit_node(uint32_t node) {
        ++record.nodes_visited;
        record.visited_nodes.push_back(node);
    }
    void test_triangles(uint32_t count) { record.triangles_tested += count; }
};

struct SilentObserver : bvh::NoObserver {
    void test_triangles(uint32_t) {}
};

// intersect_triangle reads vertex coordinates through the ray's axis
// permutation; known only at run time, every such read compiles to a chain of
// branches. Calling f with a copy of the ray whose permutation (one of six) is
// a compile-time constant folds them away; the values stay the same.
template <typename F>
[[gnu::always_inline]] inline auto with_constant_axes(const WatertightRay& ray, F&& f) {
    auto call = [&]<int kz, bool swapped>() {
        WatertightRay constant = ray;
        constant.kz = kz;
        constant.kx = swapped ? (kz + 2) % 3 : (kz + 1) % 3;
        constant.ky = swapped ? (kz + 1) % 3 : (kz + 2) % 3;
        return f(constant);
    };
    const bool swapped = ray.kx != (ray.kz + 1) % 3;
    switch (2 * ray.kz + swapped) {
        case 0: return call.template operator()<0, false>();
        case 1: return call.template operator()<0, true>();
        case 2: return call.template operator()<1, false>();
        case 3: return call.template operator()<1, true>();
        case 4: return call.template operator()<2, false>();
        default: return call.template operator()<2, true>();
    }
}

}  // namespace

Accelerator::Accelerator(const Scene& scene, unsigned threads) : scene_(scene) {
    const auto start = std::chrono::steady_clock::now();
    const size_t count = scene.triangles.size();
    std::vector<Bounds3> triangle_bounds(count);
    std::vector<vec3> centroids(count);
    for (size_t i = 0; i < count; ++i) {
        Bounds3 b;
        for (int k = 0; k < 3; ++k) b.extend(scene.positions[scene.triangles[i][k]]);
        if (scene.moving())
            for (int k = 0; k < 3; ++k) b.extend(scene.positions_close[scene.triangles[i][k]]);
        triangle_bounds[i] = b;
        centroids[i] = b.center();
    }
    bvh::BuildOptions options;
    options.traversal_cost = kTraversalCost;
    options.threads = threads;
    bvh_ = bvh::build_binned_sah(triangle_bounds, centroids, options);

    ordered_vertices_.reserve(3 * count);
    for (uint32_t id : bvh_.prim_ids)
        for (int k = 0; k < 3; ++k) ordered_vertices_.push_back(scene.positions[scene.triangles[id][k]]);
    if (scene.moving()) {
        ordered_vertices_close_.reserve(3 * count);
        for (uint32_t id : bvh_.prim_ids)
            for (int k = 0; k < 3; ++k)
                ordered_vertices_close_.push_back(scene.positions_close[scene.triangles[id][k]]);
    }

    bool alpha = false;
    for (const Material& m : scene.materials) alpha = alpha || m.alpha_mode != AlphaMode::Opaque;
    if (alpha) {
        ordered_alpha_.reserve(count);
        for (uint32_t id : bvh_.prim_ids)
            ordered_alpha_.push_back(scene.materials[scene.triangle_materials[id]].alpha_mode != AlphaMode::Opaque);
    }

    stats_.triangles = count;
    stats_.nodes = bvh_.nodes.size();
    stats_.leaves = bvh_.leaf_count();
    stats_.depth = bvh_.depth;
    stats_.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    stats_.sah_cost = bvh_.sah_cost(kTraversalCost);
}

std::array<vec3, 3> Accelerator::moving_triangle(uint32_t i, float time) const {
    const vec3* v = &ordered_vertices_[3 * size_t(i)];
    const vec3* w = &ordered_vertices_close_[3 * size_t(i)];
    return {lerp_position(v[0], w[0], time), lerp_position(v[1], w[1], time), lerp_position(v[2], w[2], time)};
}

// flatten: the traversal, the leaf test and the triangle test become one
// function, so the per-ray constants stay in registers.
template <bool kMoving, bool kFiltered, typename Observer>
[[gnu::flatten]] bool Accelerator::closest_hit(const Ray& ray, Hit& hit, Observer&& observer) const {
    // Spheres first: their hit shortens the ray the BVH has to follow.
    Ray clipped = ray;
    for (size_t s = 0; s < scene_.spheres.size(); ++s) {
        float t;
        if (intersect_sphere(clipped, scene_.spheres[s], t)) {
            clipped.t_max = t;
            hit = {t, uint32_t(scene_.triangles.size() + s), 0.0f, 0.0f};
        }
    }

    uint32_t nearest = kNoPrimitive;  // in leaf order
    TriangleHit nearest_hit{};
    const bool found_triangle = with_constant_axes(WatertightRay(ray), [&](const WatertightRay& watertight) {
        return bvh::traverse<bvh::Query::closest_hit>(
            bvh_, clipped,
            [&](uint32_t first, uint32_t count, float& t_max) {
                observer.test_triangles(count);
                bool found = false;
                for (uint32_t i = first; i < first + count; ++i) {
                    bool hit_here;
                    // Written out per case: an always_inline helper around the test
                    // kept flatten from inlining the traversal (GCC 12): renders 5% slower.
                    if constexpr (kFiltered) {
                        // A candidate first: a hole must leave the nearest hit as it was.
                        TriangleHit candidate;
                        if constexpr (kMoving) {
                            const auto v = moving_triangle(i, ray.time);
                            hit_here = intersect_triangle(watertight, v[0], v[1], v[2], t_max, candidate);
                        } else {
                            const vec3* v = &ordered_vertices_[3 * size_t(i)];
                            hit_here = intersect_triangle(watertight, v[0], v[1], v[2], t_max, candidate);
                        }
                        hit_here = hit_here && (!ordered_alpha_[i] ||
                                                triangle_coverage(scene_, bvh_.prim_ids[i], candidate.u, candidate.v) > 0.0f);
                        if (hit_here) nearest_hit = candidate;
                    } else if constexpr (kMoving) {
                        const auto v = moving_triangle(i, ray.time);
                        hit_here = intersect_triangle(watertight, v[0], v[1], v[2], t_max, nearest_hit);
                    } else {
                        const vec3* v = &ordered_vertices_[3 * size_t(i)];
                        hit_here = intersect_triangle(watertight, v[0], v[1], v[2], t_max, nearest_hit);
                    }
                    if (hit_here) {
                        t_max = nearest_hit.t;
                        nearest = i;
                        found = true;
                    }
                }
                return found;
            },
            observer);
    });
    if (found_triangle) {
        hit = {nearest_hit.t, bvh_.prim_ids[nearest], nearest_hit.u, nearest_hit.v};
        return true;
    }
    return hit.found();
}

template <bool kMoving, bool kFiltered, typename Observer>
[[gnu::flatten]] bool Accelerator::any_hit(const Ray& ray, float& visibility, Observer&& observer) const {
    for (const Sphere& sphere : scene_.spheres) {
        float t;
        if (intersect_sphere(ray, sphere, t)) return true;
    }
    return with_constant_axes(WatertightRay(ray), [&](const WatertightRay& watertight) {
        return bvh::traverse<bvh::Query::any_hit>(
            bvh_, ray,
            [&](uint32_t first, uint32_t count, float& t_max) {
                observer.test_triangles(count);
                TriangleHit ignored;
                for (uint32_t i = first; i < first + count; ++i) {
                    bool hit_here;
                    if constexpr (kMoving) {
                        const auto v = moving_triangle(i, ray.time);
                        hit_here = intersect_triangle(watertight, v[0], v[1], v[2], t_max, ignored);
                    } else {
                        const vec3* v = &ordered_vertices_[3 * size_t(i)];
                        hit_here = intersect_triangle(watertight, v[0], v[1], v[2], t_max, ignored);
                    }
                    if (!hit_here) continue;
                    if (!kFiltered || !ordered_alpha_[i]) return true;
                    // Each triangle sits in one leaf, so each is met once: the
                    // product over them does not depend on the order. A ray
                    // exactly through an edge two of them share meets both, as
                    // the watertight test promises; that has measure zero among
                    // the rays a render traces.
                    visibility *= 1.0f - triangle_coverage(scene_, bvh_.prim_ids[i], ignored.u, ignored.v);
                    if (!(visibility > 0.0f)) return true;
                }
                return false;
            },
            observer);
    });
}

template <typename Observer>
bool Accelerator::closest_hit(const Ray& ray, Hit& hit, Observer&& observer) const {
    const bool filtered = !ordered_alpha_.empty();
    if (scene_.moving())
        return filtered ? closest_hit<true, true>(ray, hit, observer) : closest_hit<true, false>(ray, hit, observer);
    return filtered ? closest_hit<false, true>(ray, hit, observer) : closest_hit<false, false>(ray, hit, observer);
}

template <typename Observer>
float Accelerator::visibility_of(const Ray& ray, Observer&& observer) const {
    float visibility = 1.0f;
    const bool filtered = !ordered_alpha_.empty();
    bool stopped;
    if (scene_.moving())
        stopped = filtered ? any_hit<true, true>(ray, visibility, observer)
                           : any_hit<true, false>(ray, visibility, observer);
    else
        stopped = filtered ? any_hit<false, true>(ray, visibility, observer)
                           : any_hit<false, false>(ray, visibility, observer);
    return stopped ? 0.0f : visibility;
}

bool Accelerator::intersect(const Ray& ray, Hit& hit) const {
    hit = Hit{};
    return closest_hit(ray, hit, SilentObserver{});
}

bool Accelerator::intersect(const Ray& ray, Hit& hit, TraversalStats& stats) const {
    hit = Hit{};
    return closest_hit(ray, hit, CountingObserver{stats});
}

bool Accelerator::intersect(const Ray& ray, Hit& hit, TraversalRecord& record) const {
    hit = Hit{};
    return closest_hit(ray, hit, RecordingObserver{record});
}

float Accelerator::visibility(const Ray& ray) const { return visibility_of(ray, SilentObserver{}); }

float Accelerator::visibility(const Ray& ray, TraversalStats& stats) const {
    return visibility_of(ray, CountingObserver{stats});
}

float Accelerator::visibility(const Ray& ray, TraversalRecord& record) const {
    return visibility_of(ray, RecordingObserver{record});
}

Accelerator::LevelBoxes Accelerator::boxes(int level) const {
    LevelBoxes boxes;
    const std::vector<uint32_t> levels = bvh_.node_levels();
    const std::vector<uint32_t> triangles = bvh_.subtree_prim_counts();
    for (uint32_t i = 0; i < bvh_.nodes.size(); ++i) {
        const bool wanted = level < 0 ? bvh_.nodes[i].is_leaf() : levels[i] == uint32_t(level);
        if (!wanted) continue;
        boxes.nodes.push_back(i);
        boxes.bounds.push_back(bvh_.nodes[i].bounds());
        boxes.triangles.push_back(triangles[i]);
    }
    return boxes;
}

}  // namespace rt
