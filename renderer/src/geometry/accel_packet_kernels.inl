// Packets of coherent rays (bvh/packet_traverse.inl) against the triangle
// blocks: the leaf test runs each ray that enters the leaf through the same
// watertight block test as its single-ray query, so the answers are the same.
// Included by accel_kernels.inl inside its ISA namespace.
//
// Only an opaque scene without instances takes the packet path (a moving one
// too, each ray at its own time); any other scene is traced ray by ray, and
// so is a closest-hit packet whose rays the intervals do not bound
// (load_packet).

#include "geometry/triangle_rays_test.inl"
#include "geometry/packet_triangle_cull.inl"

// A register's group of rays (8 or 16) of which fewer than this enter a
// leaf takes it ray by ray, four triangles a lane: a triangle against lanes
// of mostly absent rays wastes them. Closest-hit packets take half a
// register; shadow packets, which leave a triangle test with each ray that
// it stops, already 4 rays. Measured with bvh_bench's hard-shadow packets
// on AVX-512, 4 against 8: bunny 0.98 -> 1.02 of Embree-16, dragon_4 0.93 ->
// 0.99, dragon_3 0.92 -> 0.99, donut 0.94 -> 0.98, the rest alike; 2 slowed
// dragon_1's by 3%. Camera packets at 4 gained on the small meshes and lost
// up to 4% on dragon_1, so they keep half. With 8 lanes (AVX2), 2 slowed
// dragon_1's camera and shadow packets by 4%.
inline constexpr uint32_t kRaysPerTriangleTest = kRayLanes / 2;
inline constexpr uint32_t kShadowRaysPerTriangleTest = 4;

// Calls by_triangle(axes, rays) for each shear class whose rays of `in`
// take the leaf a triangle at a time: those with enough others of their
// class in their register. Returns the rays it handed over. Before there
// were classes, a packet whose rays split between two (38-52% of
// bvh_bench's soft-shadow packets) went ray by ray in every leaf; 1T
// against Embree-16, soft shadows went from 1.19 to 1.28 on the bunny, 1.19
// to 1.27 on dragon_3, 0.76 to 0.84 on the teapot. One class, nearly every
// camera packet, takes its own branch: as a loop of one, camera and hard
// shadow packets lost 3-8%.
template <typename ByTriangle>
[[gnu::always_inline]] inline uint32_t leaf_classes(const PacketShear& s, uint32_t in, uint32_t at_least,
                                                    ByTriangle&& by_triangle) {
    // The rays of `rays` in registers that hold at least at_least of them.
    const auto crowded = [&](uint32_t rays) {
        uint32_t crowd = 0;
        for (uint32_t first = 0; first < bvh::kPacketSize; first += kRayLanes) {
            const uint32_t group = rays & (kRayLaneBits << first);
            if (uint32_t(__builtin_popcount(group)) >= at_least) crowd |= group;
        }
        return crowd;
    };
    if (s.class_count == 1) {
        const uint32_t rays = crowded(in);
        if (rays != 0) by_triangle(s.classes[0], rays);
        return rays;
    }
    uint32_t handed = 0;
    for (uint32_t c = 0; c < s.class_count; ++c) {
        const uint32_t rays = crowded(in & s.classes[c].rays);
        if (rays == 0) continue;
        by_triangle(s.classes[c], rays);
        handed |= rays;
    }
    return handed;
}

// Tests the rays of `in`, all of shear class `axes`, against the leaf's
// triangles, one triangle at a time in leaf order, a register of rays a
// test. For each test some ray passes, calls found(first, hit, triangle,
// hits): `hit` has bit i for ray first + i, whose t, u and v are lane i of
// `hits`; it returns the bits of the rays that leave the packet. Returns the
// rays left in `in`. In a moving tree each ray meets the triangle where it
// is at the ray's time, moved by lerp_block's arithmetic. A still tree's
// packet from one origin (kSharedOrigin) moves each vertex to it once
// (intersect_triangle_rays): 1T against Embree-16, camera packets on the
// Cornell box 0.82 -> 0.84, the teapot 0.96 -> 0.98. `wide`: the leaf is
// wide to the packet (wide_leaf), and its triangles whose boxes no ray
// enters are skipped (packet_triangle_cull.inl); p.intervals must bound the
// rays.
template <bool kMoving, bool kSharedOrigin = false, typename Found>
[[gnu::always_inline]] inline uint32_t leaf_by_triangle(const AccelData& data, const bvh::PacketRays& p,
                                                        const PacketShear& s, ShearClass axes,
                                                        uint32_t first_block, uint32_t block_count, uint32_t in,
                                                        Found&& found, bool wide = false) {
    if constexpr (!kMoving && !kSharedOrigin)
        if (p.shared_origin)
            return leaf_by_triangle<false, true>(data, p, s, axes, first_block, block_count, in, found, wide);
    for (uint32_t b = first_block; b < first_block + block_count; ++b) {
        const TriangleBlock& block = data.blocks[b];
        // Blocks of three triangles or four: two, such as a quad's, save a
        // test at most, and a quad's two boxes are one.
        const uint32_t entered =
            !kMoving && wide && block.lane_used(2) ? triangles_entered(block, p.intervals) : ~0u;
        for (uint32_t lane = 0; lane < bvh::kBlockWidth; ++lane) {
            if (!block.lane_used(lane) || !(entered >> lane & 1)) continue;
            const SharedTriangle still{&block.v[0][0][lane]};
            for (uint32_t first = 0; first < p.count; first += kRayLanes) {
                const uint32_t rays = (in >> first) & kRayLaneBits;
                if (rays == 0) continue;
                RaysHits hits;
                uint32_t hit;
                if constexpr (kMoving) {
                    const TriangleBlock& motion = data.blocks_motion[b];
                    const RayLanes time = lanes_load<RayLanes>(p.time + first);
                    LaneTriangles moved;
                    for (int k = 0; k < 3; ++k)
                        for (int axis = 0; axis < 3; ++axis)
                            moved.c[k][axis] = block.v[k][axis][lane] + time * motion.v[k][axis][lane];
                    hit = intersect_triangle_rays<false>(p, s, axes, first, rays, moved, hits);
                } else {
                    hit = intersect_triangle_rays<kSharedOrigin>(p, s, axes, first, rays, still, hits);
                }
                if (hit) in &= ~(found(first, hit, block.triangle(lane), hits) << first);
                if (in == 0) return 0;
            }
        }
    }
    return in;
}

// The packet's shear constants, made in `bytes` when its first leaf needs
// them: most shadow packets from a point towards an area light leave the
// tree having entered none (63% of the teapot's soft shadows, stopped at
// the root), and the constants took a sixth of their setup. Out of line, as
// it runs at most once a packet: inlined into the leaf test, or held in a
// std::optional, it cost hard shadow packets 4-9%, the traversal's registers
// spilled around it. Closest-hit packets make theirs the same way (2% of
// camera packets enter no leaf); with that and the one-way ray tests of
// occluded_packet, 1T against Embree-16: smooth_sphere's camera packets
// 1.00 -> 1.04, the other packet figures alike.
[[gnu::noinline]] inline const PacketShear* make_shear(unsigned char* bytes, const bvh::PacketRays& p) {
    return new (bytes) PacketShear(p);
}

// The triangles a closest-hit packet query has found, structure of arrays
// (the distances are the packet's t_max): updated a register of rays at a
// time, as the packet's t_max and t_cull are read, since single-lane stores
// that a wide load then reads stall it.
struct PacketNearest {
    alignas(64) uint32_t primitive[bvh::kPacketSize];
    alignas(64) float u[bvh::kPacketSize];
    alignas(64) float v[bvh::kPacketSize];

    PacketNearest() { std::fill_n(primitive, bvh::kPacketSize, kNoPrimitive); }
};

// Takes the hits of `hit` that are nearer, or as near and of a lower
// triangle number (closest_in_leaf's rule, bvh::tie_reach), for rays first on.
[[gnu::always_inline]] inline void keep_nearer(bvh::PacketRays& p, PacketNearest& nearest, uint32_t first,
                                               uint32_t hit, uint32_t triangle, const RaysHits& hits) {
    const RayLanes t_max = lanes_load<RayLanes>(p.t_max + first);
    const RayUints primitive = lanes_load<RayUints>(nearest.primitive + first);
    const RayMask found = primitive != kNoPrimitive;
    const RayMask nearer =
        lanes_from_bits(hit) & ((hits.t < t_max) | ((hits.t == t_max) & found & (triangle < primitive)));
    lanes_store(p.t_max + first, nearer ? hits.t : t_max);
    const RayLanes tie_reach = hits.t + hits.t * bvh::kTieReach;  // bvh::tie_reach, lane by lane
    lanes_store(p.t_cull + first, nearer ? tie_reach : lanes_load<RayLanes>(p.t_cull + first));
    lanes_store(nearest.primitive + first, nearer ? RayUints{} + triangle : primitive);
    lanes_store(nearest.u + first, nearer ? hits.u : lanes_load<RayLanes>(nearest.u + first));
    lanes_store(nearest.v + first, nearer ? hits.v : lanes_load<RayLanes>(nearest.v + first));
}

// An opaque world tree only: the caller checks. The rays' hits so far
// (spheres) stay where no triangle is nearer, or with `clear_misses` (no
// spheres) become Hit{}. kMoving: the tree moves, and each ray meets it at
// its own time.
template <bool kMoving>
[[gnu::flatten]] inline void closest_packet(const AccelData& data, bvh::PacketRays& p, Hit* hits, bool clear_misses) {
    alignas(PacketShear) unsigned char shear_bytes[sizeof(PacketShear)];
    const PacketShear* shear = nullptr;
    SilentObserver none;
    PacketNearest nearest;  // the triangles', as closest_triangle keeps its own
    const auto intervals = [&](const bvh::WideNode& node, uint32_t index, float reach, float* t_entry) {
        if constexpr (kMoving) {
            alignas(32) float rows[6 * bvh::kWideWidth];
            swept_rows(node, data.bvh.motion[index], p, rows);
            return packet_box_test(rows, p.intervals, reach, t_entry);
        } else {
            return packet_box_test(node.lower[0], p.intervals, reach, t_entry);
        }
    };
    traverse_packet(data.bvh, p, (1u << p.count) - 1, intervals, [&](uint32_t first_block, uint32_t block_count,
                                                                     uint32_t in, bool wide) {
        // Forced inline (GCC's attribute; the standard one does not reach a
        // lambda's operator()): left out of line, as flatten sometimes left
        // it, the leaf loop cost camera packets on the Cornell box 7%.
        if (!shear) shear = make_shear(shear_bytes, p);
        const auto by_triangle = [&](const ShearClass& axes, uint32_t rays) __attribute__((always_inline)) {
            leaf_by_triangle<kMoving>(data, p, *shear, axes, first_block, block_count, rays,
                                      [&](uint32_t first, uint32_t hit, uint32_t triangle, const RaysHits& found) {
                                          keep_nearer(p, nearest, first, hit, triangle, found);
                                          return 0u;
                                      }, wide);
        };
        in &= ~leaf_classes(*shear, in, kRaysPerTriangleTest, by_triangle);
        for (; in != 0; in &= in - 1) {
            const uint32_t r = uint32_t(__builtin_ctz(in));
            Hit ray_nearest{p.t_max[r], nearest.primitive[r], nearest.u[r], nearest.v[r]};
            if (closest_in_leaf<kMoving, false>(data, WatertightRay4(shear->ray(r)), first_block, block_count, p.time[r],
                                              p.t_max[r], ray_nearest, none)) {
                p.t_cull[r] = bvh::tie_reach(p.t_max[r]);
                nearest.primitive[r] = ray_nearest.primitive;
                nearest.u[r] = ray_nearest.u, nearest.v[r] = ray_nearest.v;
            }
        }

    }, [&](bvh::ChildRef leaf) { prefetch_blocks<kMoving>(data, leaf); });
    for (uint32_t r = 0; r < p.count; ++r)
        if (nearest.primitive[r] != kNoPrimitive)
            hits[r] = {p.t_max[r], nearest.primitive[r], nearest.u[r], nearest.v[r]};
        else if (clear_misses)
            hits[r] = Hit{};
}

// The rays of `in` that an opaque triangle of the leaf stops: those that
// share a register with enough others a triangle at a time, the rest ray by ray.
template <bool kMoving>
[[gnu::always_inline]] inline uint32_t stopped_in_packet_leaf(const AccelData& data, const bvh::PacketRays& p,
                                                              const PacketShear& shear, uint32_t first_block,
                                                              uint32_t block_count, uint32_t in) {
    prefetch_blocks<kMoving>(data, bvh::ChildRef::leaf(first_block, block_count));
    uint32_t stopped = 0;
    // Forced inline, as closest_packet's leaf test.
    const auto by_triangle = [&](const ShearClass& axes, uint32_t rays) __attribute__((always_inline)) {
        stopped |= rays & ~leaf_by_triangle<kMoving>(data, p, shear, axes, first_block, block_count, rays,
                                                     [](uint32_t, uint32_t hit, uint32_t, const RaysHits&) {
                                                         return hit;
                                                     });
    };
    in &= ~leaf_classes(shear, in, kShadowRaysPerTriangleTest, by_triangle);
    SilentObserver none;
    for (; in != 0; in &= in - 1) {
        const uint32_t r = uint32_t(__builtin_ctz(in));
        float unused = 1.0f;  // an opaque scene's rays pass or stop
        if (stopped_in_leaf<kMoving, false>(data, WatertightRay4(shear.ray(r)), first_block, block_count, p.time[r],
                                            p.t_max[r], unused, none))
            stopped |= 1u << r;
    }
    return stopped;
}

// Returns the rays (a mask of those in `active`) an opaque triangle stops
// (bvh/packet_masked_traverse.inl). A packet that leaves a one-ray
// register's worth of rays at some node sends them on with any_triangle.
template <bool kMoving>
[[gnu::flatten]] inline uint32_t occluded_packet(const AccelData& data, const bvh::PacketRays& p, PacketLoad load,
                                                 uint32_t active) {
    alignas(PacketShear) unsigned char shear_bytes[sizeof(PacketShear)];
    const PacketShear* shear = nullptr;
    const auto leaf_test = [&](uint32_t first_block, uint32_t block_count, uint32_t in) {
        if (!shear) shear = make_shear(shear_bytes, p);
        return stopped_in_packet_leaf<kMoving>(data, p, *shear, first_block, block_count, in);
    };
    const auto single_test = [&](uint32_t r, bvh::ChildRef subtree) {
        const Ray ray{{p.origin[0][r], p.origin[1][r], p.origin[2][r]},
                      {p.direction[0][r], p.direction[1][r], p.direction[2][r]}, p.t_max[r], p.time[r]};
        float unused = 1.0f;  // an opaque scene's rays pass or stop
        return any_triangle<kMoving, false>(data, ray, unused, SilentObserver{}, subtree);
    };
    // Nodes culled by the tightest bound the rays allow: the intervals
    // around them, or around them run backwards from where they end, or the
    // box around their segments with intervals of mixed signs, or else only
    // the empty slots. Rays the intervals bound run one way along each axis,
    // and their own tests take one product a plane (rays_entering's kOneWay).
    const auto by_intervals = [&](auto one_way, const bvh::PacketIntervals& iv, float reach) {
        return occlude_masked<kMoving, decltype(one_way)::value>(data.bvh, p, active, [&](const float* rows) {
            alignas(32) float t_entry[bvh::kWideWidth];
            return packet_box_test(rows, iv, reach, t_entry);
        }, leaf_test, single_test);
    };
    if (load == PacketLoad::intervals) return by_intervals(std::true_type{}, p.intervals, packet_reach(p, active));
    SegmentLanes segments;
    if (!segment_lanes(segments, p)) return occlude_masked<kMoving>(data.bvh, p, active, occupied_slots, leaf_test, single_test);
    // Rays from one point that load_packet's intervals refused differ in
    // sign along some axis, and so do the same rays reversed.
    bvh::PacketIntervals reversed;
    if (float reach; !p.shared_origin && reverse_segments(reversed, reach, segments))
        return by_intervals(std::false_type{}, reversed, reach);
    // Rays whose directions differ in sign along some axis: the intervals
    // that allow for it (mixed_intervals), which cut soft shadows'
    // candidates where the box of the segments alone let the whole slab
    // between the point and the light through. 1T against Embree-16: the
    // teapot's soft shadows 0.84 -> 0.90, bunny 1.25 -> 1.32, dragon_3
    // 1.24 -> 1.33. For rays from one point the box cuts little the
    // intervals leave, and its six reductions and its test at every node
    // cost more than it saves (without it, soft shadows: teapot 0.99 ->
    // 1.02, bunny 1.41 -> 1.47, dragon_3 1.40 -> 1.46); rays from many
    // points around a light, among them, also take the box, which is the
    // tighter bound for them.
    const MixedIntervals mixed = mixed_intervals(p, segments);
    const float reach = packet_reach(p, active);
    if (p.shared_origin)
        return occlude_masked<kMoving>(data.bvh, p, active, [&](const float* rows) {
            return mixed_box_test(rows, mixed, reach);
        }, leaf_test, single_test);
    const SegmentBox box = segment_box(segments);
    return occlude_masked<kMoving>(data.bvh, p, active, [&](const float* rows) {
        return mixed_box_test(rows, mixed, reach) & segment_box_test(rows, box);
    }, leaf_test, single_test);
}

bool intersect_packet_with(const AccelScene& accel, const Ray* rays, uint32_t count, Hit* hits) {
    bvh::PacketRays p;
    if (count < 2 || !accel.packets_serve() ||
        load_packet(p, rays, count, bvh::PacketRays::kMaxSpread) != PacketLoad::intervals) {
        for (uint32_t i = 0; i < count; ++i) intersect_with(accel, rays[i], hits[i], SilentObserver{});
        return false;
    }
    const bool spheres = !accel.scene->spheres.empty();
    if (spheres)
        for (uint32_t i = 0; i < count; ++i)
            p.t_max[i] = p.t_cull[i] = nearest_sphere(*accel.scene, rays[i], hits[i]).t_max;
    if (accel.world.moving) {
        load_time_range(p);
        closest_packet<true>(accel.world, p, hits, !spheres);
    } else {
        closest_packet<false>(accel.world, p, hits, !spheres);
    }
    return true;
}

// Any packet whose rays have finite origins and reciprocals (load_packet)
// takes the packet traversal; the others go ray by ray.
bool visibility_packet_with(const AccelScene& accel, const Ray* rays, uint32_t count, float* visibility) {
    bvh::PacketRays p;
    const PacketLoad load =
        count < 2 || !accel.packets_serve() ? PacketLoad::refused : load_packet(p, rays, count, kInfinity);
    if (load == PacketLoad::refused) {
        for (uint32_t i = 0; i < count; ++i) visibility[i] = visibility_with(accel, rays[i], SilentObserver{});
        return false;
    }
    uint32_t active = (1u << count) - 1;
    std::fill_n(visibility, count, 1.0f);
    if (!accel.scene->spheres.empty())
        for (uint32_t i = 0; i < count; ++i)
            if (sphere_blocks(*accel.scene, rays[i])) visibility[i] = 0.0f, active &= ~(1u << i);
    if (accel.world.moving) load_time_range(p);
    uint32_t stopped = accel.world.moving ? occluded_packet<true>(accel.world, p, load, active)
                                          : occluded_packet<false>(accel.world, p, load, active);
    for (; stopped != 0; stopped &= stopped - 1) visibility[__builtin_ctz(stopped)] = 0.0f;
    return true;
}
