// Any-hit traversal of the eight-wide BVH by a packet of shadow rays, as
// Embree's hybrid packet kernels traverse: each child box is tested against
// every ray of the packet at once, a register of rays a pass, and each node
// carries the rays that entered it. A ray thus meets exactly the nodes and
// leaves its single-ray query would, and gets its answer, whatever the
// packet's shape: shadow rays from one point towards the samples of a large
// light, which may straddle an axis, or from a tile's hit points towards one
// light. A node's children are first culled, eight at a time, by one test
// for the whole packet, so that the per-ray tests go to the children some
// ray can reach: the interval test, around the rays or around them run
// backwards from where they end (reverse_segments), else the box around
// their segments and intervals that allow for mixed signs (mixed_intervals).
//
// This replaced, for shadow rays, a frustum around the packet (Reshetov et
// al., 2005) with one plane test per node and per-ray tests at the leaves
// only. bvh_bench, 1T against Embree-16, frustum -> now: hard shadows on
// the bunny 0.60 -> 1.01, dragon_3 0.67 -> 0.98, dragon_1 0.77 -> 1.04;
// soft ones 0.88 -> 1.18, 0.82 -> 1.15, 0.84 -> 1.21. The reversed
// intervals alone took hard shadows from 0.85, 0.84 and 0.91 of Embree-16,
// with the box of the segments, to those figures: that box let through 2.5
// times the children the rays entered.
//
// Compiled once per SIMD path, after packet_traverse.inl (rays_entering,
// swept_rows), inside its ISA namespace.

// Where the packet's segments origin + [0, t_max] direction start and end
// (lanes past count copy ray 0), lane by lane, and the reciprocals of their
// directions reversed: what the culls below are made of, in one pass.
struct SegmentLanes {
    RayLanes origin_low[3], origin_high[3], end_low[3], end_high[3];
    RayLanes back_inv_low[3], back_inv_high[3];
    RayLanes t_high;
};

// False when some t_max is infinite: the segments are then unbounded.
[[gnu::always_inline]] inline bool segment_lanes(SegmentLanes& s, const bvh::PacketRays& p) {
    for (uint32_t first = 0; first < bvh::kPacketSize; first += kRayLanes) {
        const RayLanes t_max = lanes_load<RayLanes>(p.t_max + first);
        if (lanes_bits(t_max < kInfinity) != kRayLaneBits) return false;
        const bool start = first == 0;
        s.t_high = start ? t_max : lanes_max(s.t_high, t_max);
        for (int axis = 0; axis < 3; ++axis) {
            const RayLanes origin = lanes_load<RayLanes>(p.origin[axis] + first);
            const RayLanes end = origin + t_max * lanes_load<RayLanes>(p.direction[axis] + first);
            const RayLanes back_inv = -lanes_load<RayLanes>(p.inv_direction[axis] + first);
            s.origin_low[axis] = start ? origin : lanes_min(s.origin_low[axis], origin);
            s.origin_high[axis] = start ? origin : lanes_max(s.origin_high[axis], origin);
            s.end_low[axis] = start ? end : lanes_min(s.end_low[axis], end);
            s.end_high[axis] = start ? end : lanes_max(s.end_high[axis], end);
            s.back_inv_low[axis] = start ? back_inv : lanes_min(s.back_inv_low[axis], back_inv);
            s.back_inv_high[axis] = start ? back_inv : lanes_max(s.back_inv_high[axis], back_inv);
        }
    }
    return true;
}

// [low, high] widened for rounding: a box test's rounding lets a ray enter a
// box a few ulps beyond its segment's exact end, and the ends are rounded
// too; a margin far above both, relative to the coordinates, keeps every
// such box in.
inline void widen(float& low, float& high) {
    const float margin = 1e-5f * std::max(std::abs(low), std::abs(high)) + 1e-30f;
    low -= margin, high += margin;
}

// The box around every segment.
struct SegmentBox {
    float lower[3], upper[3];
};

[[gnu::always_inline]] inline SegmentBox segment_box(const SegmentLanes& s) {
    SegmentBox box;
    for (int axis = 0; axis < 3; ++axis) {
        box.lower[axis] = lanes_low(lanes_min(s.origin_low[axis], s.end_low[axis]));
        box.upper[axis] = lanes_high(lanes_max(s.origin_high[axis], s.end_high[axis]));
        widen(box.lower[axis], box.upper[axis]);
    }
    return box;
}

// Bit i: child i's box overlaps the segments' box. An empty slot's inverted
// box overlaps nothing. `rows`: a node's plane rows, or swept_rows.
[[gnu::always_inline]] inline uint32_t segment_box_test(const float* rows, const SegmentBox& box) {
    NodeMask overlap = NodeMask{} - 1;
    for (int axis = 0; axis < 3; ++axis) {
        const NodeLanes lower = lanes_load<NodeLanes>(rows + axis * bvh::kWideWidth);
        const NodeLanes upper = lanes_load<NodeLanes>(rows + (3 + axis) * bvh::kWideWidth);
        overlap &= (lower <= box.upper[axis]) & (upper >= box.lower[axis]);
    }
    return lanes_bits(overlap);
}

struct MaskedPending {
    uint32_t ref;
    uint32_t rays;  // those that entered its box
};

// Intervals around the packet's segments run backwards, from their far
// ends, and how far they reach: shadow rays from a tile's hit points towards
// one light meet there, so seen from the light they make a thin cone, which
// the interval test bounds about as tightly as a camera's rays, where the
// box of the segments holds the whole slab between. False when the
// intervals would not bound the reversed rays (bound_rays).
[[gnu::always_inline]] inline bool reverse_segments(bvh::PacketIntervals& iv, float& reach, const SegmentLanes& s) {
    float end_low[3], end_high[3], inv_low[3], inv_high[3];
    for (int axis = 0; axis < 3; ++axis) {
        end_low[axis] = lanes_low(s.end_low[axis]), end_high[axis] = lanes_high(s.end_high[axis]);
        widen(end_low[axis], end_high[axis]);
        inv_low[axis] = lanes_low(s.back_inv_low[axis]), inv_high[axis] = lanes_high(s.back_inv_high[axis]);
    }
    reach = lanes_high(s.t_high) * (1.0f + 1e-5f);
    return bound_rays(iv, end_low, end_high, inv_low, inv_high, bvh::PacketRays::kMaxReversedSpread);
}

// Intervals around rays whose directions differ in sign along some axis,
// which the interval test (bound_rays) refuses: a light's samples from one
// point, seen straight along an axis. Along such an axis each ray still
// enters a box no earlier than where it crosses the box's near face, the
// lower one for the rays that rise and the upper for those that fall, so
// the larger of the two bounds of those crossings bounds every ray that
// enters at all; the axis bounds no exit. The other axes are bound_rays'.
struct MixedIntervals {
    // Per axis, a node's rows: two entry bounds, (row - origin) * inverse,
    // and an exit bound, raised to at least far_floor (+infinity: none).
    uint32_t near_row[3], other_row[3], far_row[3];
    float near_origin[3], other_origin[3], far_origin[3];
    float near_inv[3], other_inv[3], far_inv[3];
    float far_floor[3];
};

// The packet's rays, their origins and reciprocals as `s` and p bound them.
// Rounding is monotone: a ray's reciprocal is at least the smallest
// positive one, or at most the largest negative one, as computed, so the
// products bound each ray's rounded distances as packet_box_test's do.
[[gnu::always_inline]] inline MixedIntervals mixed_intervals(const bvh::PacketRays& p, const SegmentLanes& s) {
    MixedIntervals m;
    constexpr uint32_t kUpper = 3 * bvh::kWideWidth;
    for (int axis = 0; axis < 3; ++axis) {
        RayLanes rising = lanes_splat<RayLanes>(kInfinity), falling = lanes_splat<RayLanes>(-kInfinity);
        for (uint32_t first = 0; first < bvh::kPacketSize; first += kRayLanes) {
            const RayLanes inv = lanes_load<RayLanes>(p.inv_direction[axis] + first);
            const RayLanes zero = lanes_splat<RayLanes>(0.0f);
            rising = lanes_min(rising, inv > zero ? inv : lanes_splat<RayLanes>(kInfinity));
            falling = lanes_max(falling, inv < zero ? inv : lanes_splat<RayLanes>(-kInfinity));
        }
        // The smallest positive reciprocal and the largest negative one.
        const float rise = lanes_low(rising), fall = lanes_high(falling);
        const float origin_low = lanes_low(s.origin_low[axis]), origin_high = lanes_high(s.origin_high[axis]);
        const uint32_t lower = uint32_t(axis) * bvh::kWideWidth, upper = lower + kUpper;
        // One sign: bound_rays' planes, with no limit to the spread.
        if (rise == kInfinity) {  // every ray falls
            const float steepest = -lanes_high(s.back_inv_high[axis]);  // the most negative reciprocal
            m.near_row[axis] = m.other_row[axis] = upper, m.far_row[axis] = lower;
            m.near_origin[axis] = m.other_origin[axis] = origin_low, m.far_origin[axis] = origin_high;
            m.near_inv[axis] = m.other_inv[axis] = fall, m.far_inv[axis] = steepest * bvh::kExitScale;
            m.far_floor[axis] = -kInfinity;
        } else if (fall == -kInfinity) {  // every ray rises
            const float steepest = -lanes_low(s.back_inv_low[axis]);  // the largest reciprocal
            m.near_row[axis] = m.other_row[axis] = lower, m.far_row[axis] = upper;
            m.near_origin[axis] = m.other_origin[axis] = origin_high, m.far_origin[axis] = origin_low;
            m.near_inv[axis] = m.other_inv[axis] = rise, m.far_inv[axis] = steepest * bvh::kExitScale;
            m.far_floor[axis] = -kInfinity;
        } else {
            m.near_row[axis] = lower, m.other_row[axis] = upper, m.far_row[axis] = lower;
            m.near_origin[axis] = origin_high, m.other_origin[axis] = origin_low, m.far_origin[axis] = 0.0f;
            m.near_inv[axis] = rise, m.other_inv[axis] = fall, m.far_inv[axis] = 1.0f;
            m.far_floor[axis] = kInfinity;
        }
    }
    return m;
}

// Bit i: some ray may enter child i's box before `reach` (MixedIntervals).
[[gnu::always_inline]] inline uint32_t mixed_box_test(const float* rows, const MixedIntervals& m, float reach) {
    NodeLanes enter = lanes_splat<NodeLanes>(0.0f);
    NodeLanes exit = lanes_splat<NodeLanes>(reach);
    for (int axis = 0; axis < 3; ++axis) {
        const NodeLanes near = (lanes_load<NodeLanes>(rows + m.near_row[axis]) - m.near_origin[axis]) * m.near_inv[axis];
        const NodeLanes other =
            (lanes_load<NodeLanes>(rows + m.other_row[axis]) - m.other_origin[axis]) * m.other_inv[axis];
        // A floor of +infinity (an axis of both signs) wins over any
        // product, an empty slot's infinite planes included.
        const NodeLanes far = lanes_max((lanes_load<NodeLanes>(rows + m.far_row[axis]) - m.far_origin[axis]) *
                                            m.far_inv[axis],
                                        lanes_splat<NodeLanes>(m.far_floor[axis]));
        enter = lanes_max(enter, lanes_max(near, other));
        exit = lanes_min(exit, far);
    }
    return lanes_entered(enter, exit, lanes_splat<NodeLanes>(reach));
}

// Bit i: child i is no empty slot. For packets with no bounded box to cull by.
[[gnu::always_inline]] inline uint32_t occupied_slots(const float* rows) {
    NodeMask occupied = NodeMask{} - 1;
    for (int axis = 0; axis < 3; ++axis)
        occupied &= lanes_load<NodeLanes>(rows + axis * bvh::kWideWidth) <=
                    lanes_load<NodeLanes>(rows + (3 + axis) * bvh::kWideWidth);
    return lanes_bits(occupied);
}

// A node entered by at most this many of the packet's rays sends each on
// alone, its single-ray traversal starting there: a child test of a whole
// register for a few rays wastes it. As Embree's hybrid kernels switch
// (their switchThreshold). Over 0, 1, 2, 4, 6, 8 and 11, 4-8 served soft
// shadows best (1.15-1.2 of Embree-16 against 0.85-0.95 at 0). Measured
// again once leaves took each shear class a triangle at a time, over 0, 1,
// 2, 3, 6, 8 and 10: hard shadows from 1.00-1.05 of Embree-16 at 6 to
// 1.03-1.11 at 3 (bunny, dragon_3, dragon_1, the teapot), as fast at 1 and
// 2; soft ones alike at 3 and 6 (1.26-1.29), slower below.
inline constexpr uint32_t kSingleRays = 3;

// Starts with the rays in `active`. cull(rows) gives the children some ray
// may enter (a superset: each ray's own test follows), from a node's plane
// rows. leaf_test(first_block, block_count, rays) tests the leaf's
// primitives against `rays`, those that enter its box, and returns the ones
// it stopped, which leave the packet. single_test(ray, subtree) runs one ray's
// own any-hit query from a node on, and says whether it was stopped.
// kOneWay: the rays run one way along each axis, as p.intervals says (a
// packet load_packet bound), so each ray's own test of a child takes two
// products an axis instead of four (rays_entering).
// Returns the rays stopped.
template <bool kMoving, bool kOneWay = false, typename Cull, typename LeafTest, typename SingleTest>
[[gnu::always_inline]] inline uint32_t occlude_masked(const bvh::WideBvh& bvh, const bvh::PacketRays& p,
                                                      uint32_t active, Cull&& cull, LeafTest&& leaf_test,
                                                      SingleTest&& single_test) {
    if (bvh.empty() || active == 0) return 0;
    const uint32_t all = active;
    const auto no_prefetch = [](bvh::ChildRef) {};
    MaskedPending stack[bvh::kWideStackSize];
    uint32_t stack_size = 0;
    MaskedPending current{bvh::ChildRef::inner(0).bits, active};
    for (;;) {
        const bvh::ChildRef ref{current.ref};
        uint32_t rays = current.rays & active;
        if (rays != 0 && !ref.is_leaf() && uint32_t(__builtin_popcount(rays)) <= kSingleRays) {
            for (; rays != 0; rays &= rays - 1) {
                const uint32_t r = uint32_t(__builtin_ctz(rays));
                if (single_test(r, ref)) active &= ~(1u << r);
            }
            if (active == 0) return all;
        } else if (rays != 0 && !ref.is_leaf()) {
            const bvh::WideNode& node = bvh.nodes[ref.node()];
            const bvh::WideBoxes* motion = kMoving ? &bvh.motion[ref.node()] : nullptr;
            uint32_t candidates;
            if constexpr (kMoving) {
                alignas(32) float rows[6 * bvh::kWideWidth];
                swept_rows(node, *motion, p, rows);
                candidates = cull(rows);
            } else {
                candidates = cull(node.lower[0]);
            }
            // Slot order, as a single ray's any-hit query takes them: the
            // highest slots onto the stack first, the lowest taken now.
            uint32_t next = 0, next_rays = 0;
            for (uint32_t rest = candidates; rest != 0;) {
                const uint32_t slot = 31u - uint32_t(__builtin_clz(rest));
                rest &= ~(1u << slot);
                const uint32_t entering = rays_entering<kOneWay>(node, motion, slot, p, rays);
                if (entering == 0) continue;
                if (next_rays != 0) {
                    prefetch_child(bvh, bvh::ChildRef{next}, no_prefetch);
                    stack[stack_size++] = {next, next_rays};
                }
                next = node.child[slot].bits, next_rays = entering;
            }
            if (next_rays != 0) {
                current = {next, next_rays};
                continue;
            }
        } else if (rays != 0) {
            active &= ~leaf_test(ref.first_block(), ref.block_count(), rays);
            if (active == 0) return all;
        }
        if (stack_size == 0) return all & ~active;
        current = stack[--stack_size];
    }
}
