// Packets of coherent rays (bvh/packet_traverse.inl) against the triangle
// blocks: the leaf test runs each ray that enters the leaf through the same
// watertight block test as its single-ray query, so the answers are the same.
// Included by accel_kernels.inl inside its ISA namespace.
//
// Only a still, opaque scene without instances takes the packet path; any
// other scene, and a packet whose rays do not share their direction signs
// (PacketRays::from_rays), is traced ray by ray.

// The watertight constants of each ray, made once per packet.
struct PacketWatertight {
    alignas(16) unsigned char storage[bvh::kPacketSize][sizeof(WatertightRay4)];

    PacketWatertight(const Ray* rays, uint32_t count) {
        for (uint32_t i = 0; i < count; ++i) new (storage[i]) WatertightRay4(WatertightRay{rays[i]});
    }
    const WatertightRay4& operator[](uint32_t i) const {
        return *std::launder(reinterpret_cast<const WatertightRay4*>(storage[i]));
    }
};
static_assert(std::is_trivially_destructible_v<WatertightRay4>);

// A still, opaque world tree only: the caller checks.
[[gnu::flatten]] inline void closest_packet(const AccelData& data, bvh::PacketRays& p, const Ray* rays, Hit* hits) {
    const PacketWatertight watertight(rays, p.count);
    const uint32_t all = (1u << p.count) - 1;
    SilentObserver none;
    traverse_packet<bvh::Query::closest_hit>(data.bvh, p, all, [&](uint32_t first_block, uint32_t block_count,
                                                                   uint32_t rays_in) {
        prefetch_blocks<false>(data, bvh::ChildRef::leaf(first_block, block_count));
        const uint32_t end = first_block + block_count;
        for (; rays_in != 0; rays_in &= rays_in - 1) {
            const uint32_t r = uint32_t(__builtin_ctz(rays_in));
            for (uint32_t b = first_block; b < end; b += 2) {
                TriangleBlock unused[2];
                const TriangleBlock* pair[2];
                const uint32_t count = blocks_at<false>(data, b, end, 0.0f, unused, pair, none);
                PairHits found;
                for (uint32_t lanes = intersect_block_pair(watertight[r], pair, count, p.t_max[r], found);
                     lanes != 0; lanes &= lanes - 1) {
                    const uint32_t lane = uint32_t(__builtin_ctz(lanes));
                    if (!(found.t(lane) < p.t_max[r])) continue;
                    p.t_max[r] = found.t(lane);
                    hits[r] = {found.t(lane), pair[lane >> 2]->triangle(lane & 3), found.u(lane), found.v(lane)};
                }
            }
        }
    });
}

// Returns the rays an opaque triangle stops, as a mask.
[[gnu::flatten]] inline uint32_t occluded_packet(const AccelData& data, bvh::PacketRays& p, const Ray* rays,
                                                 uint32_t active) {
    const PacketWatertight watertight(rays, p.count);
    uint32_t stopped = 0;
    SilentObserver none;
    traverse_packet<bvh::Query::any_hit>(data.bvh, p, active, [&](uint32_t first_block, uint32_t block_count,
                                                                  uint32_t rays_in) {
        prefetch_blocks<false>(data, bvh::ChildRef::leaf(first_block, block_count));
        const uint32_t end = first_block + block_count;
        uint32_t stopped_here = 0;
        for (; rays_in != 0; rays_in &= rays_in - 1) {
            const uint32_t r = uint32_t(__builtin_ctz(rays_in));
            for (uint32_t b = first_block; b < end; b += 2) {
                TriangleBlock unused[2];
                const TriangleBlock* pair[2];
                const uint32_t count = blocks_at<false>(data, b, end, 0.0f, unused, pair, none);
                PairHits found;
                if (intersect_block_pair(watertight[r], pair, count, p.t_max[r], found) != 0) {
                    stopped_here |= 1u << r;
                    break;
                }
            }
        }
        stopped |= stopped_here;
        return stopped_here;
    });
    return stopped;
}

// Whether the packet path serves this scene.
inline bool packet_path(const AccelScene& accel) {
    return !accel.instanced() && !accel.world.moving && !accel.world.filtered && !accel.world.bvh.empty();
}

bool intersect_packet_with(const AccelScene& accel, const Ray* rays, uint32_t count, Hit* hits) {
    bvh::PacketRays p;
    if (count < 2 || !packet_path(accel) || !p.from_rays(rays, count)) {
        for (uint32_t i = 0; i < count; ++i) intersect_with(accel, rays[i], hits[i], SilentObserver{});
        return false;
    }
    const Scene& scene = *accel.scene;
    // Spheres first, ray by ray, as intersect_with: they shorten the rays.
    for (uint32_t i = 0; i < count; ++i) {
        hits[i] = Hit{};
        for (size_t s = 0; s < scene.spheres.size(); ++s) {
            float t;
            Ray clipped = rays[i];
            clipped.t_max = p.t_max[i];
            if (intersect_sphere(clipped, scene.spheres[s], t)) {
                p.t_max[i] = t;
                hits[i] = {t, uint32_t(scene.triangles.size() + s), 0.0f, 0.0f};
            }
        }
    }
    closest_packet(accel.world, p, rays, hits);
    return true;
}

bool visibility_packet_with(const AccelScene& accel, const Ray* rays, uint32_t count, float* visibility) {
    bvh::PacketRays p;
    if (count < 2 || !packet_path(accel) || !p.from_rays(rays, count)) {
        for (uint32_t i = 0; i < count; ++i) visibility[i] = visibility_with(accel, rays[i], SilentObserver{});
        return false;
    }
    uint32_t active = 0;
    for (uint32_t i = 0; i < count; ++i) {
        visibility[i] = 1.0f;
        for (const Sphere& sphere : accel.scene->spheres) {
            float t;
            if (intersect_sphere(rays[i], sphere, t)) {
                visibility[i] = 0.0f;
                break;
            }
        }
        if (visibility[i] != 0.0f) active |= 1u << i;
    }
    uint32_t stopped = occluded_packet(accel.world, p, rays, active);
    for (; stopped != 0; stopped &= stopped - 1) visibility[__builtin_ctz(stopped)] = 0.0f;
    return true;
}
