// Closest-hit traversal of the eight-wide BVH by a packet of coherent rays
// (packet_rays.h), compiled once per SIMD path like wide_traverse.inl, after
// it, inside the ISA namespace. Inner nodes take one interval test for the
// whole packet; a leaf is then offered to the rays that enter its own box,
// tested ray by ray exactly as wide_box_test tests it, so each ray meets the
// triangles its single-ray traversal would reach and gets the same answer.
//
// After packet_lanes.inl and packet_setup.inl.

// The interval slab test (Boulos et al.) on boxes side by side in lanes:
// planes(axis, near, far) gives each box's entry and exit planes along
// `axis` as the intervals pick them (near_row, far_row). Returns the lower
// bound of where any ray enters each box (at least 0), and in `exit` the
// upper bound of where any leaves it before t_max.
template <typename Lanes, typename Planes>
[[gnu::always_inline]] inline Lanes interval_entry(const bvh::PacketIntervals& iv, float t_max, Planes&& planes,
                                                   Lanes& exit) {
    Lanes t_near[3], t_far[3];
    for (int axis = 0; axis < 3; ++axis) {
        // The corners of the interval product that matter: a ray's entry
        // distance is at least the nearest origin's distance to the plane
        // over the reciprocal of least magnitude, where that distance is
        // positive (where it is not, the product is not either, and the
        // entry stays 0); its exit at most the farthest origin's over the
        // reciprocal of most. Rounding is monotone, so these bound every ray's
        // rounded distances too, its exit scaled as WideBoxRay's is.
        Lanes near, far;
        planes(axis, near, far);
        t_near[axis] = (near - iv.near_origin[axis]) * iv.near_inv[axis];
        t_far[axis] = (far - iv.far_origin[axis]) * iv.far_inv[axis];
    }
    exit = slab_exit(t_far, lanes_splat<Lanes>(t_max));
    const Lanes enter = slab_entry(t_near);
    return enter;
}

// Bit i: some ray the intervals bound may enter child i's box before t_max;
// t_entry[i] is then a lower bound of where any does (at least 0).
// `rows`: a node's plane rows, its lower[3][8] then its upper[3][8].
[[gnu::always_inline]] inline uint32_t packet_box_test(const float* rows, const bvh::PacketIntervals& iv, float t_max,
                                                       float* t_entry) {
    NodeLanes exit;
    const NodeLanes enter = interval_entry<NodeLanes>(
        iv, t_max,
        [&](int axis, NodeLanes& near, NodeLanes& far) __attribute__((always_inline)) {
            near = lanes_load<NodeLanes>(rows + iv.near_row[axis]);
            far = lanes_load<NodeLanes>(rows + iv.far_row[axis]);
        },
        exit);
    __builtin_memcpy(t_entry, &enter, sizeof enter);
    return lanes_entered(enter, exit, lanes_splat<NodeLanes>(t_max));
}

// A moving node's plane rows over the packet's times: per row the lower of
// its rows at time_low and time_high for the lower planes, the higher for
// the upper ones. The boxes at any time between lie within, as
// open + t * motion is monotone in t, rounding included; each ray's own
// box is the single-ray test's (wide_box_test's plane_row).
[[gnu::always_inline]] inline void swept_rows(const bvh::WideNode& node, const bvh::WideBoxes& motion,
                                              const bvh::PacketRays& p, float* rows) {
    const float* open = node.lower[0];
    const float* moves = motion.lower[0];
    for (uint32_t row = 0; row < 6; ++row) {
        const NodeLanes at_open = lanes_load<NodeLanes>(open + row * bvh::kWideWidth);
        const NodeLanes by = lanes_load<NodeLanes>(moves + row * bvh::kWideWidth);
        const NodeLanes early = at_open + p.time_low * by, late = at_open + p.time_high * by;
        lanes_store(rows + row * bvh::kWideWidth, row < 3 ? lanes_min(early, late) : lanes_max(early, late));
    }
}

// Which of the rays in `rays` enter child `slot`'s box before their own
// t_cull: wide_box_test's operations in its order, a register of rays a pass. Each
// ray's entry plane is the one it meets first, whichever way it runs: with a
// finite reciprocal (load_packet checks) the two distances are ordered as
// the ray's own choice of planes orders them, bit for bit.
// `motion`: a moving node's box motion, each ray's box taken at its own time
// as its single-ray test takes it; null for a still tree.
// kOneWay: the rays run one way along each axis (a packet the intervals
// bound), so the intervals' rows are each ray's own near and far planes, as
// its single-ray test picks them: two products an axis instead of four and
// their comparisons.
template <bool kOneWay = false>
[[gnu::always_inline]] inline uint32_t rays_entering(const bvh::WideNode& node, const bvh::WideBoxes* motion,
                                                     uint32_t slot, const bvh::PacketRays& p, uint32_t rays) {
    uint32_t entering = 0;
    for (uint32_t first = 0; first < p.count; first += kRayLanes) {
        if (((rays >> first) & kRayLaneBits) == 0) continue;
        const RayLanes t_max = lanes_load<RayLanes>(p.t_cull + first);
        RayLanes t_near[3], t_far[3];
        for (int axis = 0; axis < 3; ++axis) {
            const RayLanes origin = lanes_load<RayLanes>(p.origin[axis] + first);
            const RayLanes inv = lanes_load<RayLanes>(p.inv_direction[axis] + first);
            if constexpr (kOneWay) {
                // Rows as offsets from lower[0], as WideBoxRay's.
                const auto plane = [&](uint32_t row) {
                    const float at_open = (&node.lower[0][0])[row + slot];
                    if (!motion) return lanes_splat<RayLanes>(at_open);
                    return at_open + lanes_load<RayLanes>(p.time + first) * (&motion->lower[0][0])[row + slot];
                };
                t_near[axis] = (plane(p.intervals.near_row[axis]) - origin) * inv;
                t_far[axis] = (plane(p.intervals.far_row[axis]) - origin) * (inv * bvh::kExitScale);
                continue;
            }
            RayLanes lower = lanes_splat<RayLanes>(node.lower[axis][slot]);
            RayLanes upper = lanes_splat<RayLanes>(node.upper[axis][slot]);
            if (motion) {
                const RayLanes time = lanes_load<RayLanes>(p.time + first);
                lower = node.lower[axis][slot] + time * motion->lower[axis][slot];
                upper = node.upper[axis][slot] + time * motion->upper[axis][slot];
            }
            // The exit plane's distance as WideBoxRay::inv_exit gives it:
            // scaling keeps the order of the two, so the larger is the exit.
            const RayLanes inv_exit = inv * bvh::kExitScale;
            const RayLanes to_lower = lower - origin, to_upper = upper - origin;
            t_near[axis] = lanes_min(to_lower * inv, to_upper * inv);
            t_far[axis] = lanes_max(to_lower * inv_exit, to_upper * inv_exit);
        }
        const RayLanes enter = slab_entry(t_near), exit = slab_exit(t_far, t_max);
        entering |= lanes_entered(enter, exit, t_max) << first;
    }
    return entering & rays;
}

struct PacketPending {
    uint32_t ref;
    float t_entry;
    uint32_t parent;  // the node whose child it is, and which one: a leaf's box
    uint32_t slot;
};

// The largest t_cull of the rays in `rays`: no ray of the packet looks further.
[[gnu::always_inline]] inline float packet_reach(const bvh::PacketRays& p, uint32_t rays) {
    RayLanes reach = {};
    for (uint32_t first = 0; first < bvh::kPacketSize; first += kRayLanes)
        reach = lanes_max(reach, lanes_from_bits(rays >> first) ? lanes_load<RayLanes>(p.t_cull + first) : RayLanes{});
    return lanes_high(reach);
}

// How wide a leaf must look from a packet's origin for its triangles to be
// culled one by one before their tests (geometry/packet_triangle_cull.inl):
// its largest side over its distance. A 4 x 4 camera packet of a 1024-pixel
// view spans about 0.003 of its distance, so such a leaf is some thirty
// packets wide. Over 0.02, 0.1 and a footprint-relative bound (32 and 128
// packet widths, which needed the rays' spread each packet and lost 7% on
// every mesh), 0.1 gave the Cornell box's camera packets the most (1T
// against Embree-16, 1.06 against 1.04) for the same cost on meshes.
inline constexpr float kWideLeaf = 0.1f;

// Whether child `slot` of `parent` is wide: its largest side against its
// centre's distance from the packet's origin (ray 0's), taken along the axis
// it lies farthest on.
[[gnu::always_inline]] inline bool wide_leaf(const bvh::WideNode& parent, uint32_t slot, const bvh::PacketRays& p) {
    float side = 0.0f, distance = 0.0f;
    for (int axis = 0; axis < 3; ++axis) {
        const float lower = parent.lower[axis][slot], upper = parent.upper[axis][slot];
        side = std::max(side, upper - lower);
        distance = std::max(distance, std::abs(0.5f * (lower + upper) - p.origin[axis][0]));
    }
    return side >= kWideLeaf * distance;
}

// Closest-hit traversal. node_test(node, index, reach, t_entry) says which
// children some ray of the packet may enter before `reach`, with lower
// bounds of where in t_entry (packet_box_test). leaf_test(first_block,
// block_count, rays, wide) tests the leaf's primitives against the rays (a
// mask) that enter its box, and lowers their p.t_max (and t_cull) to the
// hits it finds; `wide`: the leaf is wide_leaf. prefetch_leaf(leaf) starts
// fetching a leaf's primitives as it is
// put aside, as the single-ray traversal does: 1T against Embree-16, camera
// packets on dragon_1 went from 1.04 to 1.12, the donut's from 0.99 to
// 1.01, against fetching each leaf as it is reached. Shadow packets, which
// often stop before the leaves they put aside, lost 4-6% the same way and
// fetch at the leaf. Starts with the rays in `active`. (Shadow rays take
// packet_masked_traverse.inl.)
template <typename NodeTest, typename LeafTest, typename PrefetchLeaf>
[[gnu::always_inline]] inline void traverse_packet(const bvh::WideBvh& bvh, bvh::PacketRays& p, uint32_t active,
                                                   NodeTest&& node_test, LeafTest&& leaf_test,
                                                   PrefetchLeaf&& prefetch_leaf) {
    if (bvh.empty() || active == 0) return;
    float reach = packet_reach(p, active);
    PacketPending stack[bvh::kWideStackSize];
    uint32_t stack_size = 0;
    PacketPending current{bvh::ChildRef::inner(0).bits, 0.0f, 0, 0};
    for (;;) {
        const bvh::ChildRef ref{current.ref};
        if (!ref.is_leaf()) {
            const bvh::WideNode& node = bvh.nodes[ref.node()];
            alignas(32) float t_entry[bvh::kWideWidth];
            uint32_t hits = node_test(node, ref.node(), reach, t_entry);
            if (hits != 0) {
                const uint32_t parent = ref.node();
                // One child or two: no sorting loop, as the single-ray
                // traversal's push_sorted takes them.
                if (const uint32_t rest = hits & (hits - 1); (rest & (rest - 1)) == 0) {
                    uint32_t near = uint32_t(__builtin_ctz(hits));
                    if (rest != 0) {
                        uint32_t far = uint32_t(__builtin_ctz(rest));
                        // Ties go to the lower slot, as the sort's keys order them.
                        if (t_entry[far] < t_entry[near]) std::swap(near, far);
                        prefetch_child(bvh, node.child[far], prefetch_leaf);
                        stack[stack_size++] = {node.child[far].bits, t_entry[far], parent, far};
                    }
                    current = {node.child[near].bits, t_entry[near], parent, near};
                    continue;
                }
                // The nearest taken now, the others onto the stack in slot
                // order: a packet's entry bounds order its children only
                // roughly, and sorting them all cost more than the order
                // saved. 1T against Embree-16, camera packets on the donut
                // 1.00 -> 1.04, dragon_1 1.12 -> 1.17, the others alike.
                uint64_t nearest_key = ~uint64_t(0);
                for (uint32_t rest = hits; rest != 0; rest &= rest - 1) {
                    const uint32_t slot = uint32_t(__builtin_ctz(rest));
                    uint32_t bits;
                    __builtin_memcpy(&bits, &t_entry[slot], sizeof bits);
                    nearest_key = std::min(nearest_key, uint64_t(bits) << 32 | slot);
                }
                const uint32_t s = uint32_t(nearest_key);
                for (uint32_t rest = hits & ~(1u << s); rest != 0; rest &= rest - 1) {
                    const uint32_t slot = uint32_t(__builtin_ctz(rest));
                    prefetch_child(bvh, node.child[slot], prefetch_leaf);
                    stack[stack_size++] = {node.child[slot].bits, t_entry[slot], parent, slot};
                }
                current = {node.child[s].bits, t_entry[s], parent, s};
                continue;
            }
        } else {
            const bvh::WideBoxes* motion = bvh.motion.empty() ? nullptr : &bvh.motion[current.parent];
            const uint32_t rays = rays_entering<true>(bvh.nodes[current.parent], motion, current.slot, p, active);
            if (rays != 0) {
                // A moving leaf's triangles are not culled (they move): no need to ask.
                leaf_test(ref.first_block(), ref.block_count(), rays,
                          !motion && wide_leaf(bvh.nodes[current.parent], current.slot, p));
                reach = packet_reach(p, active);
            }
        }
        for (;;) {
            if (stack_size == 0) return;
            current = stack[--stack_size];
            if (current.t_entry < reach) break;
        }
    }
}
