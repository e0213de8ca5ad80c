// The scene's ray queries over the wide BVH and its triangle blocks, compiled
// once per SIMD path: accel_generic.cpp and accel_avx_kernels.inl (AVX2 and
// AVX-512) include this inside their ISA namespace, after wide_box_test for
// that path and bvh/wide_traverse.inl. Everything here is defined per ISA, so
// no function compiled for AVX is ever shared with code that runs without it.
//
// kMoving: the scene moves; kFiltered: some triangle has alpha, and hits on it
// pass the hit filter. Template flags, so a still, opaque scene's leaves pay
// nothing for motion or alpha they do not have.

template <bool kMoving>
[[gnu::always_inline]] inline const TriangleBlock& block_at(const AccelData& data, uint32_t b, float time,
                                                           TriangleBlock& moved) {
    if constexpr (kMoving) {
        lerp_block(data.blocks[b], data.blocks_motion[b], time, moved);
        return moved;
    } else {
        return data.blocks[b];
    }
}

template <typename Observer>
[[gnu::always_inline]] inline void count_tested(Observer& observer, const TriangleBlock& block);

// Blocks b and b + 1 (when before `end`) as they are at `time`, tested
// together against one t_max by every path; returns how many there are.
template <bool kMoving, typename Observer>
[[gnu::always_inline]] inline uint32_t blocks_at(const AccelData& data, uint32_t b, uint32_t end, float time,
                                                 TriangleBlock (&moved)[2], const TriangleBlock* (&pair)[2],
                                                 Observer& observer) {
    const uint32_t count = b + 1 < end ? 2 : 1;
    for (uint32_t k = 0; k < count; ++k) {
        pair[k] = &block_at<kMoving>(data, b + k, time, moved[k]);
        count_tested(observer, *pair[k]);
    }
    return count;
}

// A leaf's blocks, 160 bytes each (and their motion in a moving scene).
template <bool kMoving>
[[gnu::always_inline]] inline void prefetch_blocks(const AccelData& data, bvh::ChildRef leaf) {
    const char* first = reinterpret_cast<const char*>(&data.blocks[leaf.first_block()]);
    const size_t bytes = size_t(leaf.block_count()) * sizeof(TriangleBlock);
    for (size_t line = 0; line < bytes; line += 64) __builtin_prefetch(first + line);
    if constexpr (kMoving) {
        const char* motion = reinterpret_cast<const char*>(&data.blocks_motion[leaf.first_block()]);
        for (size_t line = 0; line < bytes; line += 64) __builtin_prefetch(motion + line);
    }
}

template <typename Observer>
[[gnu::always_inline]] inline void count_tested(Observer& observer, const TriangleBlock& block) {
    if constexpr (!std::is_same_v<Observer, SilentObserver>) {
        uint32_t used = 0;
        for (uint32_t lane = 0; lane < bvh::kBlockWidth; ++lane) used += block.lane_used(lane);
        observer.test_triangles(used);
    }
}

// One ray against a leaf's blocks: the nearest triangle with t < t_max into
// `nearest`, lowering t_max to it. Returns whether it found one. Shared by
// the single-ray and the packet queries (accel_packet_kernels.inl).
template <bool kMoving, bool kFiltered, typename Observer>
[[gnu::always_inline]] inline bool closest_in_leaf(const AccelData& data, const WatertightRay4& watertight,
                                                   uint32_t first_block, uint32_t block_count, float time,
                                                   float& t_max, Hit& nearest, Observer& observer) {
    bool found_here = false;
    const uint32_t end = first_block + block_count;
    for (uint32_t b = first_block; b < end; b += 2) {
        TriangleBlock moved[2];
        const TriangleBlock* pair[2];
        const uint32_t count = blocks_at<kMoving>(data, b, end, time, moved, pair, observer);
        PairHits hits;
        // Once a triangle is found, one at the same distance may still win.
        const float limit = nearest.found() ? bvh::tie_reach(t_max) : t_max;
        uint32_t lanes = intersect_block_pair(watertight, pair, count, limit, hits);
        for (; lanes != 0; lanes &= lanes - 1) {
            const uint32_t lane = uint32_t(__builtin_ctz(lanes));
            const TriangleBlock& block = *pair[lane >> 2];
            const uint32_t slot = lane & 3;
            // Among equal distances the lower triangle number wins, in
            // whatever order the leaves come (bvh::tie_reach).
            if (!(hits.t(lane) < t_max ||
                  (hits.t(lane) == t_max && nearest.found() && block.triangle(slot) < nearest.primitive)))
                continue;
            // A hole leaves the nearest hit as it was.
            if (kFiltered && block.has_alpha(slot) &&
                !(triangle_coverage(*data.scene, block.triangle(slot), hits.u(lane), hits.v(lane)) > 0.0f))
                continue;
            t_max = hits.t(lane);
            nearest = {hits.t(lane), block.triangle(slot), hits.u(lane), hits.v(lane)};
            found_here = true;
        }
    }
    return found_here;
}

// One ray against a leaf's blocks: whether an opaque triangle with t < t_max
// stops it; scales `visibility` by the BLEND surfaces it passes. Shared like
// closest_in_leaf.
template <bool kMoving, bool kFiltered, typename Observer>
[[gnu::always_inline]] inline bool stopped_in_leaf(const AccelData& data, const WatertightRay4& watertight,
                                                   uint32_t first_block, uint32_t block_count, float time,
                                                   float t_max, float& visibility, Observer& observer) {
    const uint32_t end = first_block + block_count;
    for (uint32_t b = first_block; b < end; b += 2) {
        TriangleBlock moved[2];
        const TriangleBlock* pair[2];
        const uint32_t count = blocks_at<kMoving>(data, b, end, time, moved, pair, observer);
        PairHits hits;
        uint32_t lanes = intersect_block_pair(watertight, pair, count, t_max, hits);
        if (lanes == 0) continue;
        if (!kFiltered) return true;
        for (; lanes != 0; lanes &= lanes - 1) {
            const uint32_t lane = uint32_t(__builtin_ctz(lanes));
            const TriangleBlock& block = *pair[lane >> 2];
            const uint32_t slot = lane & 3;
            if (!block.has_alpha(slot)) return true;
            // Each triangle sits in one leaf, so each is met once: the
            // product over them does not depend on the order.
            visibility *= 1.0f - triangle_coverage(*data.scene, block.triangle(slot), hits.u(lane), hits.v(lane));
            if (!(visibility > 0.0f)) return true;
        }
    }
    return false;
}

// The ray's shear constants, made when the first leaf needs them: an
// incoherent ray often leaves the tree having entered no leaf, and the
// constants' axis choice branches on the direction, which such rays make
// unpredictable.
class LazyShear {
  public:
    explicit LazyShear(const Ray& ray) : ray_(ray) {}
    [[gnu::always_inline]] const WatertightRay4& get() {
        if (!made_) {
            watertight_ = WatertightRay4(WatertightRay{ray_});
            made_ = true;
        }
        return watertight_;
    }

  private:
    const Ray& ray_;
    bool made_ = false;
    // Unset until made: zeroing it, or an empty asm that marks it set, kept
    // it out of registers and cost random rays 2-5%.
    WatertightRay4 watertight_;
};

// The nearest triangle of one tree with t < ray.t_max, into `hit` when found.
// flatten: the traversal, the leaf test and the triangle test become one
// function, so the per-ray constants stay in registers.
template <bool kMoving, bool kFiltered, typename Observer>
[[gnu::flatten]] bool closest_triangle(const AccelData& data, const Ray& ray, Hit& hit, Observer observer) {
    LazyShear shear(ray);
    Hit nearest;
    const bool found = traverse_wide<bvh::Query::closest_hit, kMoving>(
        data.bvh, ray,
        [&](uint32_t first_block, uint32_t block_count, float& t_max) {
            return closest_in_leaf<kMoving, kFiltered>(data, shear.get(), first_block, block_count, ray.time, t_max,
                                                       nearest, observer);
        },
        [&](bvh::ChildRef leaf) { prefetch_blocks<kMoving>(data, leaf); }, observer);
    if (found) hit = nearest;
    return found;
}

// Returns whether an opaque triangle of one tree stopped the ray; scales
// `visibility` by the BLEND surfaces it passed.
template <bool kMoving, bool kFiltered, typename Observer>
[[gnu::flatten]] bool any_triangle(const AccelData& data, const Ray& ray, float& visibility, Observer observer,
                                   bvh::ChildRef start = bvh::ChildRef::inner(0)) {
    LazyShear shear(ray);
    return traverse_wide<bvh::Query::any_hit, kMoving>(
        data.bvh, ray,
        [&](uint32_t first_block, uint32_t block_count, float& t_max) {
            return stopped_in_leaf<kMoving, kFiltered>(data, shear.get(), first_block, block_count, ray.time, t_max,
                                                       visibility, observer);
        },
        [&](bvh::ChildRef leaf) { prefetch_blocks<kMoving>(data, leaf); }, observer, start);
}

// One tree, with the kernels its flags call for.
template <typename Observer>
bool closest_in(const AccelData& data, const Ray& ray, Hit& hit, Observer observer) {
    if (data.moving)
        return data.filtered ? closest_triangle<true, true>(data, ray, hit, observer)
                             : closest_triangle<true, false>(data, ray, hit, observer);
    return data.filtered ? closest_triangle<false, true>(data, ray, hit, observer)
                         : closest_triangle<false, false>(data, ray, hit, observer);
}

template <typename Observer>
bool any_in(const AccelData& data, const Ray& ray, float& visibility, Observer observer) {
    if (data.moving)
        return data.filtered ? any_triangle<true, true>(data, ray, visibility, observer)
                             : any_triangle<true, false>(data, ray, visibility, observer);
    return data.filtered ? any_triangle<false, true>(data, ray, visibility, observer)
                         : any_triangle<false, false>(data, ray, visibility, observer);
}

// The ray in an entry's space: the world tree's is the world's.
[[gnu::always_inline]] inline LocalRay entry_ray(const AccelScene& accel, uint32_t entry, const Ray& ray, float t_max) {
    if (entry != AccelScene::kWorldEntry) return accel.scene->instances[entry].local_ray(ray, t_max);
    LocalRay world{ray, 1.0f};
    world.ray.t_max = t_max;
    return world;
}

// Calls visit(entry) for each entry of a top-level leaf, while it returns false.
template <typename Visit>
[[gnu::always_inline]] inline bool for_entries(const AccelScene& accel, uint32_t first_block, uint32_t block_count,
                                               Visit&& visit) {
    const uint32_t* entry = &accel.top.prim_ids[size_t(first_block) * bvh::kBlockWidth];
    const uint32_t* end = entry + size_t(block_count) * bvh::kBlockWidth;
    for (; entry != end; ++entry)
        if (*entry != bvh::kNoPrim && visit(*entry)) return true;
    return false;
}

// The closest hit among the trees the top level leads to; kMoving when some entry moves.
template <bool kMoving, typename Observer>
bool closest_through_top(const AccelScene& accel, const Ray& clipped, Hit& nearest, Observer observer) {
    return traverse_wide<bvh::Query::closest_hit, kMoving>(
        accel.top, clipped,
        [&](uint32_t first_block, uint32_t block_count, float& t_max) {
            bool found_here = false;
            for_entries(accel, first_block, block_count, [&](uint32_t entry) {
                Hit h;
                const LocalRay local = entry_ray(accel, entry, clipped, t_max);
                if (closest_in(accel.tree_of(entry), local.ray, h, nested(observer, entry))) {
                    h.t /= local.t_scale;
                    if (!(h.t < t_max)) return false;  // the rounding of the scale
                    t_max = h.t;
                    nearest = h;
                    nearest.instance = entry == AccelScene::kWorldEntry ? kNoInstance : entry;
                    found_here = true;
                }
                return false;
            });
            return found_here;
        },
        [](bvh::ChildRef) {}, observer);
}

// The nearest sphere into `hit` (else no hit), and the ray shortened to it:
// spheres go first, since their hit shortens the ray the trees follow.
inline Ray nearest_sphere(const Scene& scene, const Ray& ray, Hit& hit) {
    hit = Hit{};
    Ray clipped = ray;
    for (size_t s = 0; s < scene.spheres.size(); ++s) {
        float t;
        if (intersect_sphere(clipped, scene.spheres[s], t)) {
            clipped.t_max = t;
            hit = {t, uint32_t(scene.triangles.size() + s), 0.0f, 0.0f};
        }
    }
    return clipped;
}

inline bool sphere_blocks(const Scene& scene, const Ray& ray) {
    for (const Sphere& sphere : scene.spheres) {
        float t;
        if (intersect_sphere(ray, sphere, t)) return true;
    }
    return false;
}

template <typename Observer>
bool intersect_with(const AccelScene& accel, const Ray& ray, Hit& hit, Observer observer) {
    const Ray clipped = nearest_sphere(*accel.scene, ray, hit);
    if (!accel.instanced()) {
        closest_in(accel.world, clipped, hit, observer);
        return hit.found();
    }
    Hit nearest;
    const bool found = accel.top.motion.empty() ? closest_through_top<false>(accel, clipped, nearest, observer)
                                               : closest_through_top<true>(accel, clipped, nearest, observer);
    if (found) hit = nearest;
    return hit.found();
}

// Whether something the top level leads to stops the ray; kMoving when some entry moves.
template <bool kMoving, typename Observer>
bool any_through_top(const AccelScene& accel, const Ray& ray, float& visibility, Observer observer) {
    return traverse_wide<bvh::Query::any_hit, kMoving>(
        accel.top, ray,
        [&](uint32_t first_block, uint32_t block_count, float& t_max) {
            return for_entries(accel, first_block, block_count, [&](uint32_t entry) {
                return any_in(accel.tree_of(entry), entry_ray(accel, entry, ray, t_max).ray, visibility,
                              nested(observer, entry));
            });
        },
        [](bvh::ChildRef) {}, observer);
}

template <typename Observer>
float visibility_with(const AccelScene& accel, const Ray& ray, Observer observer) {
    if (sphere_blocks(*accel.scene, ray)) return 0.0f;
    float visibility = 1.0f;
    bool stopped;
    if (!accel.instanced())
        stopped = any_in(accel.world, ray, visibility, observer);
    else if (accel.top.motion.empty())
        stopped = any_through_top<false>(accel, ray, visibility, observer);
    else
        stopped = any_through_top<true>(accel, ray, visibility, observer);
    return stopped ? 0.0f : visibility;
}

#include "geometry/accel_packet_kernels.inl"

const AccelKernels kKernels = {
    [](const AccelScene& d, const Ray& r, Hit& h) { return intersect_with(d, r, h, SilentObserver{}); },
    [](const AccelScene& d, const Ray& r, Hit& h, TraversalStats& s) { return intersect_with(d, r, h, CountingObserver{s}); },
    [](const AccelScene& d, const Ray& r, Hit& h, TraversalRecord& rec) {
        return intersect_with(d, r, h, RecordingObserver{rec});
    },
    [](const AccelScene& d, const Ray& r) { return visibility_with(d, r, SilentObserver{}); },
    [](const AccelScene& d, const Ray& r, TraversalStats& s) { return visibility_with(d, r, CountingObserver{s}); },
    [](const AccelScene& d, const Ray& r, TraversalRecord& rec) { return visibility_with(d, r, RecordingObserver{rec}); },
    intersect_packet_with,
    visibility_packet_with,
};
