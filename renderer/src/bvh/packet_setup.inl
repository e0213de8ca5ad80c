// A packet's rays into a PacketRays (packet_rays.h), eight lanes at a time,
// compiled once per SIMD path inside its ISA namespace after packet_lanes.inl.
// Setting a packet up ray by ray (a division and a comparison chain per ray
// and axis) took a third of a camera packet's time on the dragons.

// What a packet's rays allow, as load_packet finds them.
enum class PacketLoad {
    // Some ray has an infinite origin or direction reciprocal: ray by ray.
    refused,
    // Each ray's constants are set, but the intervals would not bound the
    // rays, or not tightly: they share neither their origin nor their
    // direction, differ in some direction sign, or spread their reciprocals
    // past kMaxSpread. A frustum may still bound them (packet_frustum.inl).
    rays,
    // The interval test bounds them too.
    intervals,
};

[[gnu::always_inline]] inline PacketLoad load_packet(bvh::PacketRays& p, const Ray* rays, uint32_t n) {
    p.count = n;
    for (uint32_t i = 0; i < bvh::kPacketSize; ++i) {
        const Ray& ray = rays[i < n ? i : 0];
        for (int axis = 0; axis < 3; ++axis) {
            p.origin[axis][i] = ray.origin[axis];
            p.direction[axis][i] = ray.direction[axis];
        }
        p.t_max[i] = p.t_cull[i] = ray.t_max;
    }
    // Rays from one point (a pinhole camera's) or along one direction (an
    // orthographic one's) make a cone or a beam the intervals bound tightly.
    // Rays from many points in many directions (shadow rays from a tile's
    // hits) do not: each axis' bounds then pair one ray's origin with
    // another's reciprocal, and on the full dragon such packets were 2.5
    // times slower than their rays one by one.
    PacketMask same_origin = PacketMask{} - 1, same_direction = same_origin;
    const PacketLanes zero = lanes_splat(0.0f), infinity = lanes_splat(kInfinity);
    PacketMask usable = same_origin;
    PacketLanes o_low[3], o_high[3], inv_low[3], inv_high[3];
    for (int axis = 0; axis < 3; ++axis) {
        const PacketLanes o0 = lanes_splat(p.origin[axis][0]), d0 = lanes_splat(p.direction[axis][0]);
        for (uint32_t first = 0; first < bvh::kPacketSize; first += 8) {
            const PacketLanes o = lanes_load(p.origin[axis] + first), d = lanes_load(p.direction[axis] + first);
            const PacketLanes inv = lanes_splat(1.0f) / d;
            lanes_store(p.inv_direction[axis] + first, inv);
            same_origin &= o == o0;
            same_direction &= d == d0;
            usable &= (lanes_abs(o) < infinity) & (lanes_abs(inv) < infinity) & (inv != zero);
            o_low[axis] = first == 0 ? o : lanes_min(o_low[axis], o);
            o_high[axis] = first == 0 ? o : lanes_max(o_high[axis], o);
            inv_low[axis] = first == 0 ? inv : lanes_min(inv_low[axis], inv);
            inv_high[axis] = first == 0 ? inv : lanes_max(inv_high[axis], inv);
        }
    }
    if (lanes_bits(usable) != 0xffu) return PacketLoad::refused;
    if (lanes_bits(same_origin) != 0xffu && lanes_bits(same_direction) != 0xffu) return PacketLoad::rays;
    for (int axis = 0; axis < 3; ++axis) {
        const float low = lanes_low(inv_low[axis]), high = lanes_high(inv_high[axis]);
        const bool negative = high < 0.0f;
        if (!negative && low < 0.0f) return PacketLoad::rays;
        // The product's bounds grow with the reciprocals' spread: where a
        // direction component nears 0 it can span decades, and the packet
        // would enter every box along the other axes.
        const float spread = negative ? low / high : high / low;
        if (!(spread <= bvh::PacketRays::kMaxSpread)) return PacketLoad::rays;
        p.inv_low[axis] = low, p.inv_high[axis] = high;
        constexpr uint32_t kUpper = 3 * bvh::kWideWidth;
        p.near_row[axis] = uint32_t(axis) * bvh::kWideWidth + (negative ? kUpper : 0);
        p.far_row[axis] = uint32_t(axis) * bvh::kWideWidth + (negative ? 0 : kUpper);
        // (plane - origin) * inv is increasing in the plane - origin
        // difference for positive reciprocals and decreasing for negative.
        p.near_origin[axis] = negative ? lanes_low(o_low[axis]) : lanes_high(o_high[axis]);
        p.far_origin[axis] = negative ? lanes_high(o_high[axis]) : lanes_low(o_low[axis]);
    }
    return PacketLoad::intervals;
}
