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
    SilentObserver none;
    traverse_packet<bvh::Query::closest_hit>(data.bvh, p, (1u << p.count) - 1, [&](uint32_t first_block,
                                                                               uint32_t block_count, uint32_t in) {
        prefetch_blocks<false>(data, bvh::ChildRef::leaf(first_block, block_count));
        for (; in != 0; in &= in - 1) {
            const uint32_t r = uint32_t(__builtin_ctz(in));
            closest_in_leaf<false, false>(data, watertight[r], first_block, block_count, 0.0f, p.t_max[r], hits[r],
                                          none);
        }
    });
}

// Returns the rays (a mask of those in `active`) an opaque triangle stops.
[[gnu::flatten]] inline uint32_t occluded_packet(const AccelData& data, bvh::PacketRays& p, const Ray* rays,
                                                 uint32_t active) {
    const PacketWatertight watertight(rays, p.count);
    SilentObserver none;
    uint32_t stopped = 0;
    traverse_packet<bvh::Query::any_hit>(data.bvh, p, active, [&](uint32_t first_block, uint32_t block_count,
                                                                  uint32_t in) {
        prefetch_blocks<false>(data, bvh::ChildRef::leaf(first_block, block_count));
        uint32_t stopped_here = 0;
        for (; in != 0; in &= in - 1) {
            const uint32_t r = uint32_t(__builtin_ctz(in));
            float unused = 1.0f;  // an opaque scene's rays pass or stop
            if (stopped_in_leaf<false, false>(data, watertight[r], first_block, block_count, 0.0f, p.t_max[r],
                                              unused, none))
                stopped_here |= 1u << r;
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
    for (uint32_t i = 0; i < count; ++i) p.t_max[i] = nearest_sphere(*accel.scene, rays[i], hits[i]).t_max;
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
        const bool blocked = sphere_blocks(*accel.scene, rays[i]);
        visibility[i] = blocked ? 0.0f : 1.0f;
        active |= uint32_t(!blocked) << i;
    }
    for (uint32_t stopped = occluded_packet(accel.world, p, rays, active); stopped != 0; stopped &= stopped - 1)
        visibility[__builtin_ctz(stopped)] = 0.0f;
    return true;
}
