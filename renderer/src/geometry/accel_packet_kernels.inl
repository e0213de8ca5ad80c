// Packets of coherent rays (bvh/packet_traverse.inl) against the triangle
// blocks: the leaf test runs each ray that enters the leaf through the same
// watertight block test as its single-ray query, so the answers are the same.
// Included by accel_kernels.inl inside its ISA namespace.
//
// Only a still, opaque scene without instances takes the packet path; any
// other scene, and a packet whose rays do not share their direction signs
// (load_packet), is traced ray by ray.

#include "geometry/triangle_rays_test.inl"

// A group of eight rays of which fewer than this enter a leaf takes it ray by
// ray, four triangles a lane: a triangle against eight lanes of mostly
// absent rays wastes them.
inline constexpr uint32_t kRaysPerTriangleTest = 6;

// The rays of `in` that take the leaf a triangle at a time, eight rays a test.
[[gnu::always_inline]] inline uint32_t rays_by_triangle(const PacketShear& s, uint32_t in) {
    if (!s.shared) return 0;
    uint32_t by_triangle = 0;
    for (uint32_t first = 0; first < bvh::kPacketSize; first += 8) {
        const uint32_t group = in & (0xffu << first);
        if (uint32_t(__builtin_popcount(group)) >= kRaysPerTriangleTest) by_triangle |= group;
    }
    return by_triangle;
}

// Calls found(ray, triangle, hit lanes' t, u, v, lane) for each ray of `in`
// that meets a triangle of the leaf nearer than its t_max, triangle after
// triangle in leaf order, eight rays a test; returns the rays left in `in`
// (found returns whether the ray leaves the packet).
template <typename Found>
[[gnu::always_inline]] inline uint32_t leaf_by_triangle(const AccelData& data, const bvh::PacketRays& p,
                                                        const PacketShear& s, uint32_t first_block,
                                                        uint32_t block_count, uint32_t in, Found&& found) {
    for (uint32_t b = first_block; b < first_block + block_count; ++b) {
        const TriangleBlock& block = data.blocks[b];
        for (uint32_t lane = 0; lane < bvh::kBlockWidth; ++lane) {
            if (!block.lane_used(lane)) continue;
            const vec3 p0 = block.vertex(lane, 0), p1 = block.vertex(lane, 1), p2 = block.vertex(lane, 2);
            for (uint32_t first = 0; first < p.count; first += 8) {
                const uint32_t rays = (in >> first) & 0xffu;
                if (rays == 0) continue;
                RaysHits hits;
                for (uint32_t hit = intersect_triangle_rays(p, s, first, rays, p0, p1, p2, hits); hit != 0;
                     hit &= hit - 1) {
                    const uint32_t l = uint32_t(__builtin_ctz(hit));
                    if (found(first + l, block.triangle(lane), hits.t[l], hits.u[l], hits.v[l]))
                        in &= ~(1u << (first + l));
                }
                if (in == 0) return 0;
            }
        }
    }
    return in;
}

// A still, opaque world tree only: the caller checks. The rays' hits so far
// (spheres) stay where no triangle is nearer.
[[gnu::flatten]] inline void closest_packet(const AccelData& data, bvh::PacketRays& p, Hit* hits) {
    const PacketShear shear(p);
    SilentObserver none;
    Hit nearest[bvh::kPacketSize];  // the triangles', as closest_triangle keeps its own
    const auto intervals = [&](const bvh::WideNode& node, float reach, float* t_entry) {
        return packet_box_test(node, p, reach, t_entry);
    };
    traverse_packet<bvh::Query::closest_hit>(data.bvh, p, (1u << p.count) - 1, intervals, [&](uint32_t first_block,
                                                                                          uint32_t block_count,
                                                                                          uint32_t in) {
        prefetch_blocks<false>(data, bvh::ChildRef::leaf(first_block, block_count));
        if (const uint32_t by_triangle = rays_by_triangle(shear, in)) {
            // closest_in_leaf's rule: the nearer hit, or at the same distance
            // the lower triangle number (bvh::tie_reach).
            leaf_by_triangle(data, p, shear, first_block, block_count, by_triangle,
                             [&](uint32_t r, uint32_t triangle, float t, float u, float v) {
                                 if (t < p.t_max[r] ||
                                     (t == p.t_max[r] && nearest[r].found() && triangle < nearest[r].primitive)) {
                                     p.t_max[r] = t;
                                     p.t_cull[r] = bvh::tie_reach(t);
                                     nearest[r] = {t, triangle, u, v};
                                 }
                                 return false;
                             });
            in &= ~by_triangle;
        }
        for (; in != 0; in &= in - 1) {
            const uint32_t r = uint32_t(__builtin_ctz(in));
            if (closest_in_leaf<false, false>(data, WatertightRay4(shear.ray(r)), first_block, block_count, 0.0f,
                                              p.t_max[r], nearest[r], none))
                p.t_cull[r] = bvh::tie_reach(p.t_max[r]);
        }
    });
    for (uint32_t r = 0; r < p.count; ++r)
        if (nearest[r].found()) hits[r] = nearest[r];
}

// Returns the rays (a mask of those in `active`) an opaque triangle stops.
// node_test: traverse_packet's.
template <typename NodeTest>
[[gnu::flatten]] inline uint32_t occluded_packet(const AccelData& data, bvh::PacketRays& p, uint32_t active,
                                                 NodeTest&& node_test) {
    const PacketShear shear(p);
    SilentObserver none;
    uint32_t stopped = 0;
    traverse_packet<bvh::Query::any_hit>(data.bvh, p, active, node_test, [&](uint32_t first_block,
                                                                             uint32_t block_count, uint32_t in) {
        prefetch_blocks<false>(data, bvh::ChildRef::leaf(first_block, block_count));
        uint32_t stopped_here = 0;
        if (const uint32_t by_triangle = rays_by_triangle(shear, in)) {
            stopped_here = by_triangle & ~leaf_by_triangle(data, p, shear, first_block, block_count, by_triangle,
                                                           [](uint32_t, uint32_t, float, float, float) { return true; });
            in &= ~by_triangle;
        }
        for (; in != 0; in &= in - 1) {
            const uint32_t r = uint32_t(__builtin_ctz(in));
            float unused = 1.0f;  // an opaque scene's rays pass or stop
            if (stopped_in_leaf<false, false>(data, WatertightRay4(shear.ray(r)), first_block, block_count, 0.0f,
                                              p.t_max[r], unused, none))
                stopped_here |= 1u << r;
        }
        stopped |= stopped_here;
        return stopped_here;
    });
    return stopped;
}

bool intersect_packet_with(const AccelScene& accel, const Ray* rays, uint32_t count, Hit* hits) {
    bvh::PacketRays p;
    if (count < 2 || !accel.packets_serve() || load_packet(p, rays, count) != PacketLoad::intervals) {
        for (uint32_t i = 0; i < count; ++i) intersect_with(accel, rays[i], hits[i], SilentObserver{});
        return false;
    }
    if (accel.scene->spheres.empty())
        std::fill_n(hits, count, Hit{});
    else
        for (uint32_t i = 0; i < count; ++i)
            p.t_max[i] = p.t_cull[i] = nearest_sphere(*accel.scene, rays[i], hits[i]).t_max;
    closest_packet(accel.world, p, hits);
    return true;
}

// Packets the intervals bound (a camera's, an orthographic one's) take the
// interval test; shadow rays towards one light take the frustum's.
bool visibility_packet_with(const AccelScene& accel, const Ray* rays, uint32_t count, float* visibility) {
    bvh::PacketRays p;
    PacketFrustum frustum;
    const PacketLoad load = count < 2 || !accel.packets_serve() ? PacketLoad::refused : load_packet(p, rays, count);
    if (load == PacketLoad::refused || (load == PacketLoad::rays && !make_frustum(frustum, p))) {
        for (uint32_t i = 0; i < count; ++i) visibility[i] = visibility_with(accel, rays[i], SilentObserver{});
        return false;
    }
    uint32_t active = 0;
    for (uint32_t i = 0; i < count; ++i) {
        const bool blocked = sphere_blocks(*accel.scene, rays[i]);
        visibility[i] = blocked ? 0.0f : 1.0f;
        active |= uint32_t(!blocked) << i;
    }
    uint32_t stopped;
    if (load == PacketLoad::intervals)
        stopped = occluded_packet(accel.world, p, active, [&](const bvh::WideNode& node, float reach, float* t_entry) {
            return packet_box_test(node, p, reach, t_entry);
        });
    else
        stopped = occluded_packet(accel.world, p, active, [&](const bvh::WideNode& node, float, float* t_entry) {
            std::fill_n(t_entry, bvh::kWideWidth, 0.0f);
            return frustum_box_test(node, frustum);
        });
    for (; stopped != 0; stopped &= stopped - 1) visibility[__builtin_ctz(stopped)] = 0.0f;
    return true;
}
