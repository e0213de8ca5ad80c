// A packet's rays into a PacketRays (packet_rays.h), a register of rays at a time,
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
    // past the limit asked. Shadow rays still take their packet traversal
    // (packet_masked_traverse.inl), which needs no such bound.
    rays,
    // The interval test bounds them too.
    intervals,
};

// A Ray is eight floats: one row of an 8 x 8 transpose.
static_assert(sizeof(Ray) == 8 * sizeof(float) && offsetof(Ray, direction) == 3 * sizeof(float) &&
              offsetof(Ray, t_max) == 6 * sizeof(float) && offsetof(Ray, time) == 7 * sizeof(float));

// Rays `first` to first + 7 (those past n: ray 0) as eight columns (origin
// x, y, z, direction x, y, z, t_max, time) by the 8 x 8 transpose of
// unpacks, shuffles and 128-bit swaps; element by element, the copy took a
// tenth of a camera packet's time.
[[gnu::always_inline]] inline void transpose_eight_rays(const Ray* rays, uint32_t n, uint32_t first,
                                                        NodeLanes column[8]) {
    typedef int32_t Pick __attribute__((vector_size(32)));
    NodeLanes r[8], t[8], u[8];
    for (uint32_t i = 0; i < 8; ++i) __builtin_memcpy(&r[i], &rays[first + i < n ? first + i : 0], sizeof r[i]);
    for (uint32_t i = 0; i < 8; i += 2) {
        t[i] = __builtin_shuffle(r[i], r[i + 1], Pick{0, 8, 1, 9, 4, 12, 5, 13});
        t[i + 1] = __builtin_shuffle(r[i], r[i + 1], Pick{2, 10, 3, 11, 6, 14, 7, 15});
    }
    for (uint32_t i = 0; i < 8; i += 4)
        for (uint32_t k = 0; k < 2; ++k) {
            u[i + 2 * k] = __builtin_shuffle(t[i + k], t[i + k + 2], Pick{0, 1, 8, 9, 4, 5, 12, 13});
            u[i + 2 * k + 1] = __builtin_shuffle(t[i + k], t[i + k + 2], Pick{2, 3, 10, 11, 6, 7, 14, 15});
        }
    // u[j] (j < 4) holds components j and j + 4 of rays 0-3 and of 4-7 in u[j + 4].
    for (uint32_t j = 0; j < 4; ++j) {
        column[j] = __builtin_shuffle(u[j], u[j + 4], Pick{0, 1, 2, 3, 8, 9, 10, 11});
        column[j + 4] = __builtin_shuffle(u[j], u[j + 4], Pick{4, 5, 6, 7, 12, 13, 14, 15});
    }
}

// A register's rays (first to first + kRayLanes - 1) as eight columns, each
// one register: with 16 lanes, two transposes joined.
template <typename Lanes>
[[gnu::always_inline]] inline void transpose_rays(const Ray* rays, uint32_t n, uint32_t first, Lanes column[8]) {
    NodeLanes low[8];
    transpose_eight_rays(rays, n, first, low);
    if constexpr (sizeof(Lanes) == 2 * sizeof(NodeLanes)) {
        NodeLanes high[8];
        transpose_eight_rays(rays, n, first + 8, high);
        for (uint32_t j = 0; j < 8; ++j)
            column[j] = __builtin_shufflevector(low[j], high[j], 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    } else {
        static_assert(sizeof(Lanes) == sizeof(NodeLanes));
        for (uint32_t j = 0; j < 8; ++j) column[j] = low[j];
    }
}

// Intervals around rays with origins in [origin_low, origin_high] and
// direction reciprocals in [inv_low, inv_high], per axis; false when they
// would not bound them at all, or spread their reciprocals past max_spread.
inline bool bound_rays(bvh::PacketIntervals& iv, const float origin_low[3], const float origin_high[3],
                       const float inv_low[3], const float inv_high[3], float max_spread) {
    for (int axis = 0; axis < 3; ++axis) {
        const float low = inv_low[axis], high = inv_high[axis];
        const bool negative = high < 0.0f;
        if (!negative && low < 0.0f) return false;
        // The product's bounds grow with the reciprocals' spread: where a
        // direction component nears 0 it can span decades, and the packet
        // would enter every box along the other axes.
        const float spread = negative ? low / high : high / low;
        if (!(spread <= max_spread)) return false;
        iv.near_inv[axis] = negative ? high : low;
        iv.far_inv[axis] = (negative ? low : high) * bvh::kExitScale;
        constexpr uint32_t kUpper = 3 * bvh::kWideWidth;
        iv.near_row[axis] = uint32_t(axis) * bvh::kWideWidth + (negative ? kUpper : 0);
        iv.far_row[axis] = uint32_t(axis) * bvh::kWideWidth + (negative ? 0 : kUpper);
        // (plane - origin) * inv is increasing in the plane - origin
        // difference for positive reciprocals and decreasing for negative.
        iv.near_origin[axis] = negative ? origin_low[axis] : origin_high[axis];
        iv.far_origin[axis] = negative ? origin_high[axis] : origin_low[axis];
    }
    return true;
}

// Sets up the packet from registers, storing each column whole: eight-lane
// stores that sixteen-lane loads read back cannot be forwarded, and stalled
// the setup for a quarter of its time. max_spread: bound_rays'.
[[gnu::always_inline]] inline PacketLoad load_packet(bvh::PacketRays& p, const Ray* rays, uint32_t n,
                                                     float max_spread) {
    p.count = n;
    constexpr uint32_t kGroups = bvh::kPacketSize / kRayLanes;
    RayLanes column[kGroups][8];
    for (uint32_t g = 0; g < kGroups; ++g) {
        transpose_rays(rays, n, g * kRayLanes, column[g]);
        for (int axis = 0; axis < 3; ++axis) {
            lanes_store(p.origin[axis] + g * kRayLanes, column[g][axis]);
            lanes_store(p.direction[axis] + g * kRayLanes, column[g][3 + axis]);
        }
        lanes_store(p.t_max + g * kRayLanes, column[g][6]);
        lanes_store(p.t_cull + g * kRayLanes, column[g][6]);
        lanes_store(p.time + g * kRayLanes, column[g][7]);
    }
    // Rays from one point (a pinhole camera's) or along one direction (an
    // orthographic one's) make a cone or a beam the intervals bound tightly.
    // Rays from many points in many directions (shadow rays from a tile's
    // hits) do not: each axis' bounds then pair one ray's origin with
    // another's reciprocal, and on the full dragon such packets were 2.5
    // times slower than their rays one by one. Origins are compared as bits:
    // -0 and +0 are equal numbers that a vertex's coordinate less them may
    // tell apart (PacketRays::shared_origin).
    RayMask same_origin = RayMask{} - 1, same_direction = same_origin;
    const RayLanes zero = lanes_splat<RayLanes>(0.0f), infinity = lanes_splat<RayLanes>(kInfinity);
    RayMask usable = same_origin;
    RayLanes o_low[3], o_high[3], inv_low[3], inv_high[3];
    for (int axis = 0; axis < 3; ++axis) {
        const RayLanes o0 = lanes_splat<RayLanes>(column[0][axis][0]), d0 = lanes_splat<RayLanes>(column[0][3 + axis][0]);
        for (uint32_t g = 0, first = 0; g < kGroups; ++g, first += kRayLanes) {
            const RayLanes o = column[g][axis], d = column[g][3 + axis];
            const RayLanes inv = lanes_splat<RayLanes>(1.0f) / d;
            lanes_store(p.inv_direction[axis] + first, inv);
            same_origin &= lanes_bitcast<RayUints>(o) == lanes_bitcast<RayUints>(o0);
            same_direction &= d == d0;
            usable &= (lanes_abs(o) < infinity) & (lanes_abs(inv) < infinity) & (inv != zero);
            o_low[axis] = first == 0 ? o : lanes_min(o_low[axis], o);
            o_high[axis] = first == 0 ? o : lanes_max(o_high[axis], o);
            inv_low[axis] = first == 0 ? inv : lanes_min(inv_low[axis], inv);
            inv_high[axis] = first == 0 ? inv : lanes_max(inv_high[axis], inv);
        }
    }
    if (lanes_bits(usable) != kRayLaneBits) return PacketLoad::refused;
    p.shared_origin = lanes_bits(same_origin) == kRayLaneBits;
    const bool shared_direction = lanes_bits(same_direction) == kRayLaneBits;
    if (!p.shared_origin && !shared_direction) return PacketLoad::rays;
    // A shared origin or direction is its own bound: no reduction across the lanes.
    float origin_low[3], origin_high[3], reciprocal_low[3], reciprocal_high[3];
    for (int axis = 0; axis < 3; ++axis) {
        if (p.shared_origin) {
            origin_low[axis] = origin_high[axis] = p.origin[axis][0];
        } else {
            origin_low[axis] = lanes_low(o_low[axis]), origin_high[axis] = lanes_high(o_high[axis]);
        }
        if (shared_direction) {
            reciprocal_low[axis] = reciprocal_high[axis] = p.inv_direction[axis][0];
        } else {
            reciprocal_low[axis] = lanes_low(inv_low[axis]), reciprocal_high[axis] = lanes_high(inv_high[axis]);
        }
    }
    if (!bound_rays(p.intervals, origin_low, origin_high, reciprocal_low, reciprocal_high, max_spread))
        return PacketLoad::rays;
    return PacketLoad::intervals;
}

// The earliest and latest of the rays' times, which a moving tree's nodes are
// swept over (swept_rows); a still tree never reads them.
[[gnu::always_inline]] inline void load_time_range(bvh::PacketRays& p) {
    RayLanes low = lanes_load<RayLanes>(p.time), high = low;
    for (uint32_t first = kRayLanes; first < bvh::kPacketSize; first += kRayLanes) {
        low = lanes_min(low, lanes_load<RayLanes>(p.time + first));
        high = lanes_max(high, lanes_load<RayLanes>(p.time + first));
    }
    p.time_low = lanes_low(low), p.time_high = lanes_high(high);
}
